/* SPDX-License-Identifier: BSD-3-Clause */
/* The plant protocol's messages (docs/physics.md, "Plant protocol"): a
 * fixed little-endian binary layout, one request from the device and one
 * reply from the plant per exchange. This module only encodes requests
 * and checks and decodes replies (the plant's bytes are outside input);
 * plant_socket.c moves them. */
#ifndef HOST_PLANT_WIRE_H
#define HOST_PLANT_WIRE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "plant.h"

#define PLANT_WIRE_VERSION 1u
#define PLANT_WIRE_HEADER 12u
#define PLANT_WIRE_NAME_MAX 32u

typedef enum {
    PLANT_MSG_HELLO = 1,
    PLANT_MSG_RESET = 2,
    PLANT_MSG_STEP = 3,
    PLANT_MSG_BODIES = 4,
    PLANT_MSG_BODY = 5,
    PLANT_MSG_CONTACTS = 6,
    PLANT_MSG_SET = 7,
} plant_msg_t;

/* HELLO's features: the scene queries the plant answers. */
#define PLANT_FEATURE_BODIES 0x1u
#define PLANT_FEATURE_CONTACTS 0x2u
#define PLANT_FEATURE_SET 0x4u

/* Payload sizes (bytes). */
#define PLANT_WIRE_HELLO_REQ 8u
#define PLANT_WIRE_HELLO_REPLY (8u + PLANT_WIRE_NAME_MAX)
#define PLANT_WIRE_RESET_REQ 4u
#define PLANT_WIRE_STEP_REQ 20u
#define PLANT_WIRE_PAD (4u + 4u * PLANT_PAD_CELLS)
#define PLANT_WIRE_SAMPLE (28u + PLANT_FINGERS * PLANT_WIRE_PAD)
#define PLANT_WIRE_BODIES_REPLY 4u
#define PLANT_WIRE_BODY_REQ 4u
#define PLANT_WIRE_BODY_REPLY (PLANT_NAME_MAX + 12u * 8u + 8u)
#define PLANT_WIRE_CONTACTS_REQ 4u
#define PLANT_WIRE_CONTACT 72u
#define PLANT_WIRE_SET_REQ 32u
/* the most contacts a reply may carry (bounds its length) */
#define PLANT_WIRE_CONTACTS_MAX 256u
#define PLANT_WIRE_PAYLOAD_MAX (8u + PLANT_WIRE_CONTACTS_MAX * PLANT_WIRE_CONTACT)

/* A reply's header. */
typedef struct {
    uint8_t version;
    uint8_t type;
    uint16_t status; /* plant_err_t */
    uint32_t length; /* the payload's bytes */
} plant_wire_header_t;

typedef struct {
    uint32_t timestep_us;
    uint32_t features;
    char name[PLANT_WIRE_NAME_MAX + 1u];
} plant_wire_hello_t;

/* A request of type with its payload into out (cap >= PLANT_WIRE_HEADER +
 * payload); returns its length. */
size_t plant_wire_request(uint8_t *out, plant_msg_t type, const uint8_t *payload, size_t len);
void plant_wire_put_u32(uint8_t *at, uint32_t v);
void plant_wire_put_f32(uint8_t *at, float v);
void plant_wire_put_f64(uint8_t *at, double v);
/* The payloads the device sends. */
void plant_wire_step_payload(uint8_t out[PLANT_WIRE_STEP_REQ], const plant_drive_t *drive,
                             uint32_t dt_us);
void plant_wire_set_payload(uint8_t out[PLANT_WIRE_SET_REQ], unsigned index, plant_set_t what,
                            const double *value);

/* A reply's header to a request of type: NULL, or what is wrong with it
 * (for the fault's message). */
const char *plant_wire_header(const uint8_t in[PLANT_WIRE_HEADER], plant_msg_t type,
                              plant_wire_header_t *out);
/* Payloads of replies with status PLANT_OK: NULL, or what is wrong. */
const char *plant_wire_hello(const uint8_t *in, size_t len, plant_wire_hello_t *out);
const char *plant_wire_sample(const uint8_t *in, size_t len, plant_sample_t *out);
const char *plant_wire_bodies(const uint8_t *in, size_t len, unsigned *count);
const char *plant_wire_body(const uint8_t *in, size_t len, plant_body_t *out);
/* Up to cap contacts into out; *total: how many the plant has. */
const char *plant_wire_contacts(const uint8_t *in, size_t len, plant_contact_t *out, unsigned cap,
                                unsigned *total);

#endif
