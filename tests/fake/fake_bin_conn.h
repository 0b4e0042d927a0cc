/* SPDX-License-Identifier: BSD-3-Clause */
/* A binary protocol client for the driver's tests: sends framed requests
 * into a connection of the fake port's device (fake_device.h) and
 * keeps every reply frame it gets, decoded, in order. */
#ifndef FAKE_BIN_CONN_H
#define FAKE_BIN_CONN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "bin/wsg_bin_frame.h"
#include "fake_device.h"

#define BC_FRAMES_MAX 512

typedef struct {
    uint8_t id;
    uint16_t status;
    uint8_t values[WSG_BIN_PAYLOAD_MAX];
    size_t values_len;
    wsg_msg_kind_t kind;
    uint64_t at_us;
} bc_frame_t;

typedef struct {
    wsg_conn_t conn;
    bc_frame_t frames[BC_FRAMES_MAX];
    size_t count;
    size_t read;
    bool bad_frame; /* a write that was not exactly one valid frame */
} bin_client_t;

extern bin_client_t bc_main;
extern bin_client_t bc_other;

/* drv NULL: auto-detected from the first byte. */
void bc_open(bin_client_t *c, wsg_transport_t transport, const wsg_proto_driver_t *drv);
/* A request with a valid CRC. */
void bc_send(bin_client_t *c, uint8_t id, const void *payload, size_t len);
/* The same with the checksum bytes given (a bad CRC, or CRC off). */
void bc_send_crc(bin_client_t *c, uint8_t id, const void *payload, size_t len, uint16_t crc);
/* Next unread frame, or NULL. */
const bc_frame_t *bc_next(bin_client_t *c);
size_t bc_unread(const bin_client_t *c);
/* Asserts the next frame's ID and status, returns it. */
const bc_frame_t *bc_expect(bin_client_t *c, uint8_t id, uint16_t status);
/* Ticks until a frame arrives, then asserts it as bc_expect does. */
const bc_frame_t *bc_await_expect(bin_client_t *c, uint8_t id, uint16_t status,
                                  uint32_t timeout_ms);
void bc_expect_none(bin_client_t *c);
float bc_f32(const bc_frame_t *f, size_t offset);

/* Shortcuts: 0x21 with flags, width, speed; 0x40-0x45 with flags, period. */
void bc_move(bin_client_t *c, uint8_t flags, float width, float speed);
void bc_query(bin_client_t *c, uint8_t id, uint8_t flags, uint16_t period_ms);
/* Homing over the binary protocol to the end (fixture). */
void bc_setup(void);
void bc_setup_homed(void);
void bc_teardown(void);

#endif
