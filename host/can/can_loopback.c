/* SPDX-License-Identifier: BSD-3-Clause */
/* The in-process finger bus (can_loopback.h). */
#include "can_loopback.h"

#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"

#define LOOPBACK_QUEUE 512u /* frames waiting for the gripper, at most */
/* Most polls bring one frame (an FMF's MEASURE every 10 ms): it waits in
 * the bus itself. One, not two: a fleet's 10 000 buses stay in the same
 * malloc size as before (a cell's peak memory is at its limit). */
#define LOOPBACK_QUEUE_INLINE 1u
/* A poll's frames fit the first heap queue: a DSA transfer (28 BULK
 * frames), the FMF's MEASURE and heartbeats. */
#define LOOPBACK_QUEUE_FIRST 32u
#define GRIPPER (-1)

/* A participant's acceptance filters, and their verdict on the identifier
 * and EXT flag of the last frame asked about (a DSA transfer is 28 frames
 * with one identifier). */
typedef struct {
    hal_can_filter_t filters[HAL_CAN_MAX_FILTERS];
    uint8_t count; /* narrow: the bus stays in its malloc size */
    bool cached, cached_verdict, cached_ext;
    uint32_t cached_id;
} acceptance_t;

/* A fleet has thousands of buses, so they are kept small: the nodes share
 * one port (a node's frames carry its node id), and a node's filters are
 * its type's (wsg_finger_node_filters), tested per frame rather than kept
 * (wsg_finger_node_accepts). */
struct can_loopback {
    finger_node_t nodes[FBUS_SLOTS];
    hal_can_t nodes_port;
    hal_can_t port;
    /* Frames for the gripper: queue[head..head + count), in a row so that
     * the gripper takes them in place (recv_many). In inline_queue, or on
     * the heap as more frames queue up, up to LOOPBACK_QUEUE; freed when a
     * poll finds nothing. */
    hal_can_frame_t *queue;
    can_loopback_tap_t tap;
    void *tap_ctx;
    /* The nodes' loop is the gripper's poll (run_nodes) */
    uint64_t polled_us;
    uint64_t nodes_due_us; /* never later than the earliest node's due_us */
    /* Before then a poll finds nothing (quiet_until_us in hal_can.h): the
     * gripper reads it at every step. */
    uint64_t quiet_until_us;
    unsigned capacity, head, count;
    uint32_t frames;
    acceptance_t accept;
    hal_can_frame_t inline_queue[LOOPBACK_QUEUE_INLINE];
};

static bool set_acceptance(acceptance_t *a, const hal_can_filter_t *filters, unsigned count)
{
    if (count > HAL_CAN_MAX_FILTERS) {
        return false;
    }
    memcpy(a->filters, filters, count * sizeof(filters[0]));
    a->count = (uint8_t)count;
    a->cached = false;
    return true;
}

static inline bool accepts(acceptance_t *a, const hal_can_frame_t *frame)
{
    bool ext = (frame->flags & HAL_CAN_FLAG_EXT) != 0u;
    if (!a->cached || frame->id != a->cached_id || ext != a->cached_ext) {
        a->cached_verdict = hal_can_filters_accept(a->filters, a->count, frame);
        a->cached_id = frame->id;
        a->cached_ext = ext;
        a->cached = true;
    }
    return a->cached_verdict;
}

/* Room for n more frames at the end of a queue without it: the frames
 * move to its start, and it doubles while below its bound; false when it
 * cannot (the bound, or out of memory). */
static bool make_room(can_loopback_t *bus, unsigned n)
{
    if (bus->head > 0u) {
        memmove(bus->queue, bus->queue + bus->head, bus->count * sizeof(bus->queue[0]));
        bus->head = 0;
    }
    if (bus->count + n <= bus->capacity) {
        return true;
    }
    bool on_heap = bus->queue != bus->inline_queue;
    unsigned capacity = on_heap ? 2u * bus->capacity : LOOPBACK_QUEUE_FIRST;
    while (capacity < bus->count + n) {
        capacity *= 2u;
    }
    if (capacity > LOOPBACK_QUEUE) {
        return false;
    }
    hal_can_frame_t *queue = realloc(on_heap ? bus->queue : NULL, capacity * sizeof(*queue));
    if (queue == NULL) {
        return false;
    }
    if (!on_heap) {
        memcpy(queue, bus->inline_queue, bus->count * sizeof(*queue));
    }
    bus->queue = queue;
    bus->capacity = capacity;
    return true;
}

static inline void to_gripper(can_loopback_t *bus, const hal_can_frame_t *frame)
{
    if (!accepts(&bus->accept, frame)) {
        return;
    }
    bool full = bus->head + bus->count == bus->capacity;
    if (full && !make_room(bus, 1)) { /* the oldest frame is lost, as on an overrun */
        bus->head++;
        bus->count--;
        make_room(bus, 1);
    }
    bus->queue[bus->head + bus->count] = *frame;
    bus->count++;
}

/* Every other participant sees the frame, as on a real bus. */
static void deliver(can_loopback_t *bus, const hal_can_frame_t *frame, int from)
{
    uint64_t now = hal_clock_now_us();
    bus->frames++;
    if (bus->tap != NULL) {
        bus->tap(bus->tap_ctx, frame, now);
    }
    if (from != GRIPPER) {
        to_gripper(bus, frame);
    }
    if (!wsg_finger_node_may_accept(frame)) {
        return; /* a node's measurement or heartbeat, for the gripper alone */
    }
    fbus_state_t state; /* every node takes a STATE that unpacks */
    bool is_state = wsg_fbus_unpack_state(frame, &state);
    for (int i = 0; i < (int)FBUS_SLOTS; i++) {
        finger_node_t *n = &bus->nodes[i];
        if (i == from) {
            continue;
        }
        if (is_state) {
            wsg_finger_node_receive_state(n, &state, now);
        } else if (wsg_finger_node_accepts(n, frame)) {
            wsg_finger_node_receive(n, frame, now);
        }
        if (n->due_us < bus->nodes_due_us) { /* a frame may power it, or wake it */
            bus->nodes_due_us = n->due_us;
        }
    }
}

/* Most frames a node sends are for the gripper alone (measurements,
 * heartbeats: deliver() would find no node to take them), and with no tap
 * they need no time either. */
static bool node_send(void *ctx, const hal_can_frame_t *frame)
{
    can_loopback_t *bus = ctx;
    if (bus->tap == NULL && !wsg_finger_node_may_accept(frame)) {
        bus->frames++;
        to_gripper(bus, frame);
        return true;
    }
    deliver(bus, frame, wsg_fbus_slot_of_node((uint8_t)(frame->id & FBUS_NODE_MASK)));
    return true;
}

/* node_send() of frames[0..count) (count > 0) at once, when it can: one
 * identifier, for the gripper alone, no tap, and room for all. */
static bool to_gripper_at_once(can_loopback_t *bus, const hal_can_frame_t *frames, unsigned count)
{
    const hal_can_frame_t *first = &frames[0];
    if (bus->tap != NULL || wsg_finger_node_may_accept(first) || !accepts(&bus->accept, first)) {
        return false;
    }
    for (unsigned i = 1; i < count; i++) {
        if (frames[i].id != first->id || frames[i].flags != first->flags) {
            return false;
        }
    }
    if (bus->head + bus->count + count > bus->capacity && !make_room(bus, count)) {
        return false;
    }
    memcpy(&bus->queue[bus->head + bus->count], frames, count * sizeof(frames[0]));
    bus->count += count;
    bus->frames += count;
    return true;
}

/* A DSA's transfer: 28 BULK frames of one identifier. */
static unsigned node_send_many(void *ctx, const hal_can_frame_t *frames, unsigned count)
{
    if (count > 0u && to_gripper_at_once(ctx, frames, count)) {
        return count;
    }
    for (unsigned i = 0; i < count; i++) {
        node_send(ctx, &frames[i]);
    }
    return count;
}

static bool node_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    (void)frame;
    return false; /* frames reach nodes by delivery, never by polling */
}

static bool node_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    (void)ctx;
    (void)filters;
    return count <= HAL_CAN_MAX_FILTERS; /* the node's own: asked per frame */
}

/* Until when a poll would find what poll_finds_nothing() looks for, as
 * the bus stands: never while frames wait or a heap queue is to be freed;
 * else until the earliest node's due time, and a stall after the last
 * poll (so that no poll the gripper skips would have been a stall). Every
 * gripper operation ends with it: all the nodes' work happens in them. */
static void note_quiet_until(can_loopback_t *bus)
{
    uint64_t unstalled = bus->polled_us + FBUS_STALL_US + 1u;
    uint64_t until = bus->nodes_due_us < unstalled ? bus->nodes_due_us : unstalled;
    bool empty = bus->count == 0u && bus->queue == bus->inline_queue;
    bus->quiet_until_us = empty ? until : 0u;
}

static bool gripper_send(void *ctx, const hal_can_frame_t *frame)
{
    can_loopback_t *bus = ctx;
    uint8_t faults;
    deliver(bus, frame, GRIPPER);
    if (wsg_fbus_unpack_simctl(frame, &faults)) {
        to_gripper(bus, frame); /* the controller wakes to watch the fault take effect */
    }
    note_quiet_until(bus);
    return true;
}

/* The nodes whose due time has come step, and the earliest due time is
 * kept. */
static void step_due_nodes(can_loopback_t *bus, uint64_t now)
{
    uint64_t due = UINT64_MAX;
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        finger_node_t *n = &bus->nodes[i];
        if (now >= n->due_us) {
            wsg_finger_node_step_due(n, now);
        }
        due = n->due_us < due ? n->due_us : due;
    }
    bus->nodes_due_us = due;
}

/* wsg_finger_node_step() of every node, with the gripper's poll as their
 * loop: they are always polled together, so one stall bookkeeping serves
 * all (done for all before any steps: a node's frames never reach another
 * node, whose acceptance takes only the gripper's frames), and nothing
 * runs before the earliest due time. Inline: most polls end here. */
static inline void run_nodes(can_loopback_t *bus, uint64_t now)
{
    uint64_t gap = now - bus->polled_us;
    if (bus->polled_us != 0u && gap > FBUS_STALL_US) {
        for (unsigned i = 0; i < FBUS_SLOTS; i++) {
            wsg_finger_node_skip_stall(&bus->nodes[i], gap, now);
        }
    }
    bus->polled_us = now;
    if (now >= bus->nodes_due_us) {
        step_due_nodes(bus, now);
    }
}

/* With no frame waiting, lets the nodes catch up with the simulated clock
 * (now); false when they sent nothing either (an idle bus holds no heap
 * queue then). */
static bool nodes_sent(can_loopback_t *bus, uint64_t now)
{
    bus->head = 0;
    run_nodes(bus, now);
    if (bus->count > 0u) {
        return true;
    }
    if (bus->queue != bus->inline_queue) {
        free(bus->queue);
        bus->queue = bus->inline_queue;
        bus->capacity = LOOPBACK_QUEUE_INLINE;
    }
    return false;
}

static bool take_one(can_loopback_t *bus, hal_can_frame_t *frame)
{
    if (bus->count == 0u && !nodes_sent(bus, hal_clock_now_us())) {
        return false;
    }
    *frame = bus->queue[bus->head];
    bus->head++;
    bus->count--;
    return true;
}

static bool gripper_recv(void *ctx, hal_can_frame_t *frame)
{
    bool taken = take_one(ctx, frame);
    note_quiet_until(ctx);
    return taken;
}

/* What nodes_sent() finds at most polls, and all it changes then: no
 * stall, no node due, no heap queue to free. */
static inline bool poll_finds_nothing(can_loopback_t *bus, uint64_t now)
{
    bool stalled = bus->polled_us != 0u && now - bus->polled_us > FBUS_STALL_US;
    if (stalled || now >= bus->nodes_due_us || bus->queue != bus->inline_queue) {
        return false;
    }
    bus->head = 0;
    bus->polled_us = now;
    return true;
}

/* All waiting frames, in place: the next call starts the queue afresh. */
static const hal_can_frame_t *take_many(can_loopback_t *bus, unsigned *count)
{
    if (bus->count == 0u) {
        uint64_t now = hal_clock_now_us();
        if (poll_finds_nothing(bus, now) || !nodes_sent(bus, now)) {
            return NULL;
        }
    }
    const hal_can_frame_t *frames = &bus->queue[bus->head];
    *count = bus->count;
    bus->head += bus->count;
    bus->count = 0;
    return frames;
}

static const hal_can_frame_t *gripper_recv_many(void *ctx, unsigned *count)
{
    const hal_can_frame_t *frames = take_many(ctx, count);
    note_quiet_until(ctx);
    return frames;
}

static const uint64_t *gripper_quiet_until_us(void *ctx)
{
    can_loopback_t *bus = ctx;
    return &bus->quiet_until_us;
}

/* The gripper skipped its polls up to last_us: what poll_finds_nothing()
 * would have done at each, the last one counting. */
static void gripper_polls_skipped(void *ctx, uint64_t last_us)
{
    can_loopback_t *bus = ctx;
    bus->head = 0;
    bus->polled_us = last_us;
    note_quiet_until(bus);
}

static bool gripper_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    can_loopback_t *bus = ctx;
    return set_acceptance(&bus->accept, filters, count);
}

/* The gripper's side runs the nodes when it polls: on demand. */
static const hal_can_ops_t gripper_ops = {
    gripper_send,      gripper_recv, gripper_set_filters,    true,
    gripper_recv_many, NULL,         gripper_quiet_until_us, gripper_polls_skipped};
static const hal_can_ops_t node_ops = {
    node_send, node_recv, node_set_filters, false, NULL, node_send_many, NULL, NULL};

can_loopback_t *can_loopback_create(const fbus_type_t types[FBUS_SLOTS],
                                    const finger_node_params_t *params)
{
    can_loopback_t *bus = calloc(1, sizeof(*bus));
    if (bus == NULL) {
        return NULL;
    }
    bus->port = (hal_can_t){&gripper_ops, bus};
    bus->nodes_port = (hal_can_t){&node_ops, bus};
    bus->queue = bus->inline_queue;
    bus->capacity = LOOPBACK_QUEUE_INLINE;
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        wsg_finger_node_init(&bus->nodes[i], types[i], i, params, &bus->nodes_port);
    }
    return bus;
}

void can_loopback_destroy(can_loopback_t *bus)
{
    if (bus != NULL) {
        if (bus->queue != bus->inline_queue) {
            free(bus->queue);
        }
        free(bus);
    }
}

void can_loopback_set_tap(can_loopback_t *bus, can_loopback_tap_t tap, void *ctx)
{
    bus->tap = tap;
    bus->tap_ctx = ctx;
}

const hal_can_t *can_loopback_bus(can_loopback_t *bus)
{
    return &bus->port;
}

uint32_t can_loopback_frames(const can_loopback_t *bus)
{
    return bus->frames;
}

void can_loopback_set_contact(can_loopback_t *bus, const finger_contact_t *contact)
{
    for (unsigned i = 0; i < FBUS_SLOTS; i++) {
        wsg_finger_node_set_contact(&bus->nodes[i], contact);
    }
}
