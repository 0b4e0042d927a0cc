/* SPDX-License-Identifier: BSD-3-Clause */
/* The in-process finger bus (can_loopback.h). */
#include "can_loopback.h"

#include <string.h>

#include "hal_clock.h"

#define LOOPBACK_RING 512u
#define GRIPPER (-1)

/* A participant's acceptance filters, and their verdict on every standard
 * identifier worked out when they are set: every frame is offered to every
 * participant, so a lookup instead of a pass over the filters. */
typedef struct {
    hal_can_filter_t filters[HAL_CAN_MAX_FILTERS];
    unsigned count;
    uint8_t std_ids[(HAL_CAN_STD_ID_MASK + 1u) / 8u]; /* bit per identifier */
} acceptance_t;

typedef struct {
    finger_node_t node;
    hal_can_t port;
    acceptance_t accept;
} loopback_node_t;

static struct {
    loopback_node_t nodes[FBUS_SLOTS];
    hal_can_t port;
    acceptance_t accept;
    hal_can_frame_t ring[LOOPBACK_RING];
    unsigned head, count;
    uint32_t frames;
} bus;

static struct {
    can_loopback_tap_t fn;
    void *ctx;
} tap; /* outside bus: can_loopback_init() keeps it */

static bool set_acceptance(acceptance_t *a, const hal_can_filter_t *filters, unsigned count)
{
    if (count > HAL_CAN_MAX_FILTERS) {
        return false;
    }
    memcpy(a->filters, filters, count * sizeof(filters[0]));
    a->count = count;
    memset(a->std_ids, 0, sizeof(a->std_ids));
    for (uint32_t id = 0; id <= HAL_CAN_STD_ID_MASK; id++) {
        hal_can_frame_t probe = {.id = id};
        if (hal_can_filters_accept(filters, count, &probe)) {
            a->std_ids[id / 8u] |= (uint8_t)(1u << (id % 8u));
        }
    }
    return true;
}

static inline bool accepts(const acceptance_t *a, const hal_can_frame_t *frame)
{
    if ((frame->flags & HAL_CAN_FLAG_EXT) != 0u || frame->id > HAL_CAN_STD_ID_MASK) {
        return hal_can_filters_accept(a->filters, a->count, frame);
    }
    return (a->std_ids[frame->id / 8u] & (1u << (frame->id % 8u))) != 0u;
}

static void to_gripper(const hal_can_frame_t *frame)
{
    if (!accepts(&bus.accept, frame)) {
        return;
    }
    if (bus.count == LOOPBACK_RING) {
        bus.head = (bus.head + 1u) % LOOPBACK_RING;
        bus.count--;
    }
    bus.ring[(bus.head + bus.count) % LOOPBACK_RING] = *frame;
    bus.count++;
}

/* Every other participant sees the frame, as on a real bus. */
static void deliver(const hal_can_frame_t *frame, int from)
{
    uint64_t now = hal_clock_now_us();
    bus.frames++;
    if (tap.fn != NULL) {
        tap.fn(tap.ctx, frame, now);
    }
    if (from != GRIPPER) {
        to_gripper(frame);
    }
    for (int i = 0; i < (int)FBUS_SLOTS; i++) {
        loopback_node_t *n = &bus.nodes[i];
        if (i != from && accepts(&n->accept, frame)) {
            wsg_finger_node_receive(&n->node, frame, now);
        }
    }
}

static bool node_send(void *ctx, const hal_can_frame_t *frame)
{
    deliver(frame, (int)(intptr_t)ctx);
    return true;
}

static bool node_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    (void)frame;
    return false; /* frames reach nodes by delivery, never by polling */
}

static bool node_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    return set_acceptance(&bus.nodes[(intptr_t)ctx].accept, filters, count);
}

static bool gripper_send(void *ctx, const hal_can_frame_t *frame)
{
    (void)ctx;
    uint8_t faults;
    deliver(frame, GRIPPER);
    if (wsg_fbus_unpack_simctl(frame, &faults)) {
        to_gripper(frame); /* the controller wakes to watch the fault take effect */
    }
    return true;
}

/* Lets the nodes catch up with the simulated clock, then hands out a frame. */
static bool gripper_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    if (bus.count == 0u) {
        uint64_t now = hal_clock_now_us();
        for (unsigned i = 0; i < FBUS_SLOTS; i++) {
            wsg_finger_node_step(&bus.nodes[i].node, now);
        }
    }
    if (bus.count == 0u) {
        return false;
    }
    *frame = bus.ring[bus.head];
    bus.head = (bus.head + 1u) % LOOPBACK_RING;
    bus.count--;
    return true;
}

static bool gripper_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    (void)ctx;
    return set_acceptance(&bus.accept, filters, count);
}

/* The gripper's side runs the nodes when it polls: on demand. */
static const hal_can_ops_t gripper_ops = {gripper_send, gripper_recv, gripper_set_filters, true};
static const hal_can_ops_t node_ops = {node_send, node_recv, node_set_filters, false};

void can_loopback_init(const fbus_type_t types[FBUS_SLOTS], const finger_node_params_t *params)
{
    memset(&bus, 0, sizeof(bus));
    bus.port = (hal_can_t){&gripper_ops, NULL};
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        loopback_node_t *n = &bus.nodes[i];
        n->port = (hal_can_t){&node_ops, (void *)(intptr_t)i};
        wsg_finger_node_init(&n->node, types[i], i, params, &n->port);
        hal_can_filter_t filters[HAL_CAN_MAX_FILTERS];
        unsigned count = wsg_finger_node_filters(&n->node, filters);
        node_set_filters((void *)(intptr_t)i, filters, count);
    }
}

void can_loopback_set_tap(can_loopback_tap_t fn, void *ctx)
{
    tap.fn = fn;
    tap.ctx = ctx;
}

const hal_can_t *can_loopback_bus(void)
{
    return &bus.port;
}

uint32_t can_loopback_frames(void)
{
    return bus.frames;
}
