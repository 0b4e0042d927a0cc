/* SPDX-License-Identifier: BSD-3-Clause */
/* A simulated finger on the finger bus (docs/finger-bus.md): a WSG-FMF
 * force-measuring finger, a WSG-DSA tactile finger or a generic finger
 * without sensor. It follows the gripper's STATE broadcast, so it needs
 * nothing but the bus: tools/fingersim runs it on SocketCAN, wsgsim on its
 * in-process loopback bus. Portable: no heap, no OS; time is passed in. */
#ifndef FINGER_NODE_H
#define FINGER_NODE_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg/finger_proto.h"
#include "hal_can.h"

typedef struct {
    float offset_n; /* FMF: force reading with nothing touching, until TARE */
    float noise_n;  /* FMF: standard deviation of the reading */
    uint32_t seed;  /* noise generator seed (0: a fixed default) */
} finger_node_params_t;

/* A finger's contact as a physics scene computes it (docs/physics.md): the
 * normal force on the finger's pad (N) and that force over its cells (N
 * per cell, FBUS_DSA_ROWS x FBUS_DSA_COLS, row-major), for the finger in
 * slot. Without one, a finger measures the force the gripper broadcasts. */
typedef struct {
    void (*read)(void *ctx, unsigned slot, float *force_n, float *cells_n);
    void *ctx;
} finger_contact_t;

/* The BULK segments of a DSA transfer. */
#define FINGER_NODE_DSA_SEGMENTS                                                                   \
    ((FBUS_DSA_ROWS * FBUS_DSA_COLS + FBUS_BULK_VALUES_PER_FRAME - 1u) / FBUS_BULK_VALUES_PER_FRAME)

typedef struct {
    /* Wider fields first, so that a fleet's thousands of nodes hold no
     * padding. */
    const hal_can_t *bus;
    const finger_contact_t *contact; /* NULL: the broadcast force */
    /* power, lifecycle and schedule */
    uint64_t powered_at_us;
    uint64_t last_state_us;
    uint64_t stepped_us; /* the last step: a longer gap than FBUS_STALL_US was a stall */
    uint64_t next_heartbeat_us;
    uint64_t next_data_us;
    /* Never later than wsg_finger_node_next_due_us() (a step before it does
     * nothing): worked out again at every step and at most frames. */
    uint64_t due_us;
    fbus_type_t type;
    finger_node_params_t params;
    fbus_state_t state; /* what the gripper last broadcast, when have_state */
    uint32_t frames_sent;
    /* FMF */
    uint32_t rng;
    float average_n; /* running mean of the raw reading, the tare reference */
    float tare_n;
    /* DSA */
    float cells_force_n; /* the force the cells show, when cells_valid */
    /* the cells as they go on the wire (wsg_fbus_bulk_wire) */
    uint8_t cells_wire[FINGER_NODE_DSA_SEGMENTS * FBUS_BULK_VALUES_PER_FRAME * 2u];
    uint8_t node;
    uint8_t slot;
    bool powered;
    bool operational;
    uint8_t sim_faults; /* FBUS_FAULT_*: injected through SIMCTL */
    bool have_state;
    uint8_t heartbeat_counter;
    uint8_t data_counter;
    bool tared;         /* FMF */
    uint8_t tare_count; /* FMF */
    bool cells_valid;   /* DSA */
} finger_node_t;

void wsg_finger_node_defaults(finger_node_params_t *params);
void wsg_finger_node_init(finger_node_t *node, fbus_type_t type, unsigned slot,
                          const finger_node_params_t *params, const hal_can_t *bus);

/* The filters the node needs on its controller (at most 3). */
unsigned wsg_finger_node_filters(const finger_node_t *node, hal_can_filter_t *out);

/* hal_can_filters_accept() with the node's wsg_finger_node_filters(), as one
 * test: a standard STATE frame, or a COMMAND or SIMCTL to this node. The
 * loopback asks it for every frame on the bus. */
static inline bool wsg_finger_node_accepts(const finger_node_t *node, const hal_can_frame_t *frame)
{
    uint32_t id = frame->id & HAL_CAN_STD_ID_MASK;
    uint32_t own = (uint32_t)(node->node & FBUS_NODE_MASK);
    return (frame->flags & HAL_CAN_FLAG_EXT) == 0u &&
           (id == FBUS_ID_STATE || id == FBUS_ID_COMMAND + own || id == FBUS_ID_SIMCTL + own);
}

/* False for a frame no node accepts (wsg_finger_node_accepts), by its
 * function code alone: anything but STATE, COMMAND and SIMCTL. */
static inline bool wsg_finger_node_may_accept(const hal_can_frame_t *frame)
{
    uint32_t func = fbus_func_of(frame->id);
    return func == FBUS_ID_STATE || func == FBUS_ID_COMMAND || func == FBUS_ID_SIMCTL;
}

/* Handles one frame from the bus (STATE, COMMAND, SIMCTL for this node). */
void wsg_finger_node_receive(finger_node_t *node, const hal_can_frame_t *frame, uint64_t now_us);
/* wsg_finger_node_receive() of a STATE frame that wsg_fbus_unpack_state()
 * made *s of: a bus unpacks its STATE (one every 10 ms) once for all its
 * nodes. */
void wsg_finger_node_receive_state(finger_node_t *node, const fbus_state_t *s, uint64_t now_us);
/* The part of wsg_finger_node_step() after the stall bookkeeping, once the
 * cached due time has come. */
void wsg_finger_node_step_due(finger_node_t *node, uint64_t now_us);

/* A powered node steps at least every heartbeat (100 ms). A longer gap means
 * its own loop was held up (the host descheduled fingersim): the gripper's
 * silence counts only while the node ran, else a stall of the whole host
 * would cut the fingers' supply. The gap is skipped: the silence before it
 * is moved forward by it (not past now_us). */
static inline void wsg_finger_node_skip_stall(finger_node_t *node, uint64_t gap_us, uint64_t now_us)
{
    uint64_t shifted = node->last_state_us + gap_us;
    node->last_state_us = shifted < now_us ? shifted : now_us;
}

/* The loop that steps the node is its own: a gap of more than FBUS_STALL_US
 * since its last step was a stall. */
static inline void wsg_finger_node_skip_own_stall(finger_node_t *node, uint64_t now_us)
{
    uint64_t gap = now_us - node->stepped_us;
    if (node->stepped_us != 0u && gap > FBUS_STALL_US) {
        wsg_finger_node_skip_stall(node, gap, now_us);
    }
    node->stepped_us = now_us;
}

/* Sends whatever is due at now_us. A node is polled far more often than it
 * has something to do (wsgsim's in-process bus steps it at every control
 * step, 1 ms while moving): inline, and nothing but the stall bookkeeping
 * before its cached due time. The bookkeeping can only move the due time
 * later (it shifts last_state_us forward), so the cached time is never
 * late. */
static inline void wsg_finger_node_step(finger_node_t *node, uint64_t now_us)
{
    wsg_finger_node_skip_own_stall(node, now_us);
    if (now_us >= node->due_us) {
        wsg_finger_node_step_due(node, now_us);
    }
}

/* When wsg_finger_node_step() must run next (UINT64_MAX: only a frame wakes it). */
uint64_t wsg_finger_node_next_due_us(const finger_node_t *node);

/* The finger's contact from now on (NULL: the broadcast force). */
void wsg_finger_node_set_contact(finger_node_t *node, const finger_contact_t *contact);

/* The DSA pressure pattern for a contact force (exposed for tests). */
void wsg_finger_node_dsa_pattern(float force_n, uint16_t *cells);

/* "A,B" or "A" (slot 1 none) -> two types; false when malformed. */
bool wsg_finger_node_parse_pair(const char *text, fbus_type_t types[FBUS_SLOTS]);

#endif
