/* SPDX-License-Identifier: BSD-3-Clause */
/* The finger-bus wire format (docs/finger-bus.md, docs/finger-bus.dbc):
 * classic 8-byte CAN frames with 11-bit identifiers, base + node id, all
 * multi-byte fields little-endian. Shared by the gripper core (finger_bus.c)
 * and the simulated finger nodes (hal/sim/finger_node.c). */
#ifndef FINGER_PROTO_H
#define FINGER_PROTO_H

#include <stdbool.h>
#include <stdint.h>

#include "hal_can.h"

#define FBUS_PROTO_VERSION 1u
#define FBUS_SLOTS 2u
#define FBUS_NODE_ID(slot) ((uint8_t)((slot) + 1u)) /* slot 0 -> node 1, slot 1 -> node 2 */
#define FBUS_NODE_MASK 0x00Fu
#define FBUS_FUNC_MASK 0x7F0u

/* Function bases; a frame's identifier is base + node id. */
#define FBUS_ID_STATE 0x080u      /* gripper -> all, node 0: jaw state and slot power */
#define FBUS_ID_COMMAND 0x0C0u    /* gripper -> node: tare, descriptor request */
#define FBUS_ID_DESCRIPTOR 0x100u /* node -> gripper: finger type and configuration */
#define FBUS_ID_MEASURE 0x180u    /* node -> gripper: one measured value (FMF force) */
#define FBUS_ID_BULK 0x200u       /* node -> gripper: one segment of a multi-frame transfer */
#define FBUS_ID_HEARTBEAT 0x700u  /* node -> gripper: node state and faults */
#define FBUS_ID_SIMCTL 0x7E0u     /* simulation only: fault injection into a node */

/* Periods and timeouts, microseconds. */
#define FBUS_STATE_PERIOD_US 10000u
#define FBUS_HEARTBEAT_PERIOD_US 100000u
#define FBUS_MEASURE_PERIOD_US 10000u
#define FBUS_BULK_PERIOD_US 50000u
#define FBUS_COMM_TIMEOUT_US 300000u     /* gripper: node silent this long -> FF_COMM_FAULT */
#define FBUS_SUPPLY_TIMEOUT_US 1000000u  /* node: no STATE this long -> unpowered */
#define FBUS_BOOT_US 20000u              /* node: power-on to operational */
#define FBUS_DESCRIPTOR_RETRY_US 100000u /* gripper: re-request a missing descriptor */
#define FBUS_TARE_RETRY_US 100000u       /* gripper: repeat a TARE the finger has not counted */
#define FBUS_TARE_SENDS 3u               /* gripper: TARE commands sent for one TARE() at most */
/* Node: a loop of its own that did not run this long was held up (its host
 * descheduled it), and its supply watchdog skips that time. */
#define FBUS_STALL_US 250000u

typedef enum {
    FBUS_TYPE_NONE = 0,
    FBUS_TYPE_GENERIC = 1,
    FBUS_TYPE_FMF = 2,
    FBUS_TYPE_DSA = 3,
} fbus_type_t;

typedef enum {
    FBUS_ENC_NONE = 0,    /* the finger delivers no data */
    FBUS_ENC_MEASURE = 1, /* one value in MEASURE frames, int32 in 1/1000 of the unit */
    FBUS_ENC_BULK = 2,    /* rows x cols uint16 values in BULK transfers */
} fbus_encoding_t;

typedef enum {
    FBUS_NODE_BOOT = 0,
    FBUS_NODE_OPERATIONAL = 1,
    FBUS_NODE_FAULT = 2
} fbus_node_state_t;

#define FBUS_FAULT_POWER 0x01u /* heartbeat fault bits; SIMCTL uses the same bits */
#define FBUS_FAULT_INIT 0x02u
#define FBUS_FAULT_UNPLUG 0x04u /* SIMCTL only: the node leaves the bus */

typedef enum { FBUS_CMD_TARE = 1, FBUS_CMD_REQ_DESCRIPTOR = 2 } fbus_command_t;

#define FBUS_DSA_ROWS 14u
#define FBUS_DSA_COLS 6u
#define FBUS_BULK_VALUES_PER_FRAME 3u
#define FBUS_BULK_MAX_VALUES 96u /* 32 segments */
#define FBUS_DSA_CELL_MAX 4095u  /* 12-bit tactile cells */

typedef struct {
    float position_mm;  /* 0.01 mm, 0..655.35 */
    float force_n;      /* motor-current force estimate, 0.01 N, 0..655.35 */
    uint8_t power_mask; /* bit i: slot i powered */
    uint8_t grip_state;
    uint8_t counter;
} fbus_state_t;

typedef struct {
    uint8_t type; /* fbus_type_t */
    uint8_t version;
    uint8_t rows;
    uint8_t cols;
    uint8_t encoding; /* fbus_encoding_t */
    uint8_t features; /* bit 0: tare supported */
    uint16_t firmware;
} fbus_descriptor_t;

#define FBUS_FEATURE_TARE 0x01u

typedef struct {
    int32_t value_milli; /* FMF: force in mN */
    uint8_t counter;
    uint8_t status; /* bit 0: tared since power-on */
    uint8_t tare_count;
} fbus_measure_t;

#define FBUS_MEASURE_TARED 0x01u

typedef struct {
    uint8_t state; /* fbus_node_state_t */
    uint8_t faults;
    uint8_t counter;
} fbus_heartbeat_t;

typedef struct {
    uint8_t segment; /* 0..127 */
    bool last;
    uint8_t transfer;
    uint16_t values[FBUS_BULK_VALUES_PER_FRAME];
} fbus_bulk_t;

/* Reassembles one BULK transfer at a time: segments 0, 1, ... with the same
 * transfer counter; a gap or a new counter restarts it. */
typedef struct {
    bool active;
    uint8_t transfer;
    uint8_t next_segment;
    uint16_t count;
    uint16_t values[FBUS_BULK_MAX_VALUES];
} fbus_bulk_rx_t;

static inline uint8_t fbus_node_of(uint32_t id)
{
    return (uint8_t)(id & FBUS_NODE_MASK);
}

static inline uint32_t fbus_func_of(uint32_t id)
{
    return id & FBUS_FUNC_MASK;
}

/* Frame identifier of a function for a node; false for an unknown node. */
uint32_t wsg_fbus_id(uint32_t func, uint8_t node);
/* The slot a node id stands for, or -1. */
static inline int wsg_fbus_slot_of_node(uint8_t node)
{
    return (node >= 1u && node <= FBUS_SLOTS) ? (int)node - 1 : -1;
}

void wsg_fbus_pack_state(hal_can_frame_t *f, const fbus_state_t *s);
bool wsg_fbus_unpack_state(const hal_can_frame_t *f, fbus_state_t *s);
void wsg_fbus_pack_command(hal_can_frame_t *f, uint8_t node, uint8_t command);
bool wsg_fbus_unpack_command(const hal_can_frame_t *f, uint8_t *command);
void wsg_fbus_pack_descriptor(hal_can_frame_t *f, uint8_t node, const fbus_descriptor_t *d);
bool wsg_fbus_unpack_descriptor(const hal_can_frame_t *f, fbus_descriptor_t *d);
void wsg_fbus_pack_measure(hal_can_frame_t *f, uint8_t node, const fbus_measure_t *m);
bool wsg_fbus_unpack_measure(const hal_can_frame_t *f, fbus_measure_t *m);
void wsg_fbus_pack_bulk(hal_can_frame_t *f, uint8_t node, const fbus_bulk_t *b);
bool wsg_fbus_unpack_bulk(const hal_can_frame_t *f, fbus_bulk_t *b);
/* A transfer's values[0..count) as they go on the wire, out[0..2 * count),
 * for wsg_fbus_pack_bulk_transfer(). */
void wsg_fbus_bulk_wire(uint8_t *out, const uint16_t *values, unsigned count);
/* frames[0..segments): what wsg_fbus_pack_bulk() makes of a transfer's
 * segments, the last one marked, from its values in wire order
 * (wsg_fbus_bulk_wire(), FBUS_BULK_VALUES_PER_FRAME a segment, the last
 * one padded with zeros). A sender whose values did not change keeps them
 * so: a transfer is then a few stores a frame (a DSA sends 28 every 50 ms). */
void wsg_fbus_pack_bulk_transfer(hal_can_frame_t *frames, uint8_t node, uint8_t transfer,
                                 const uint8_t *wire, unsigned segments);
void wsg_fbus_pack_heartbeat(hal_can_frame_t *f, uint8_t node, const fbus_heartbeat_t *h);
bool wsg_fbus_unpack_heartbeat(const hal_can_frame_t *f, fbus_heartbeat_t *h);
void wsg_fbus_pack_simctl(hal_can_frame_t *f, uint8_t node, uint8_t faults);
bool wsg_fbus_unpack_simctl(const hal_can_frame_t *f, uint8_t *faults);

void wsg_fbus_bulk_rx_reset(fbus_bulk_rx_t *rx);
/* Feeds one segment; true when it completed a transfer (rx->count values). */
bool wsg_fbus_bulk_rx_feed(fbus_bulk_rx_t *rx, const fbus_bulk_t *segment);
/* A well-formed BULK frame (what wsg_fbus_unpack_bulk() accepts). */
bool wsg_fbus_is_bulk(const hal_can_frame_t *f);
/* wsg_fbus_bulk_rx_feed() of each frame of f[0..n) that wsg_fbus_is_bulk()
 * accepts (the others are skipped), in order, without unpacking them (the
 * gripper receives 28 per DSA transfer), while they carry f[0]'s identifier
 * (one node's run of frames), until one completes a transfer (*done then
 * true): returns how many frames it took, at least 1 when n > 0. */
unsigned wsg_fbus_bulk_rx_feed_frames(fbus_bulk_rx_t *rx, const hal_can_frame_t *f, unsigned n,
                                      bool *done);

#endif
