/* SPDX-License-Identifier: BSD-3-Clause */
/* The gripper side of the finger bus (docs/finger-bus.md): powers the two
 * finger slots, broadcasts the jaw state, supervises each node (heartbeat,
 * descriptor, comm-fault timeout), collects measurements and multi-frame
 * transfers into the finger slots FTYPE/FDATA/FFLAGS read, sends TARE, and
 * computes the grip-force loop on a WSG-FMF measurement: it hands a force
 * limit to the motion supervisor, which alone drives the axis. */
#ifndef FINGER_BUS_H
#define FINGER_BUS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal_can.h"
#include "wsg/finger_proto.h"
#include "wsg/wsg_fingers.h"
#include "wsg/wsg_status.h"

#define FBUS_FORCE_KI_PER_S 4.0f   /* integral gain of the grip-force loop */
#define FBUS_FORCE_TRIM_SHARE 0.5f /* the loop may trim the motor force by this share */
#define FBUS_FORCE_WAKE_N 0.01f    /* a jaw force change that wakes an on-demand bus */

typedef struct {
    bool heard; /* a frame arrived since the slot was powered */
    bool comm_fault;
    /* what the finger's FFLAGS and FTYPE follow changed since publish()
     * last showed it (most full steps change none of it); false at power-on,
     * when the finger's reset flags and type are what a slot not heard yet
     * shows */
    bool unpublished;
    uint64_t last_rx_us;
    uint8_t node_state; /* fbus_node_state_t from the last heartbeat */
    uint8_t node_faults;
    bool config; /* descriptor received */
    fbus_descriptor_t desc;
    uint64_t desc_request_us;
    uint8_t tare_count; /* as the node last reported it */
    /* A TARE sent and not yet counted in the node's MEASURE frames: a frame
     * the node lost (a full receive queue) is sent again. */
    bool tare_pending;
    uint8_t tare_sends;        /* for the pending TARE, the repeats included */
    uint8_t tare_count_before; /* the node's count when TARE() was asked */
    uint64_t tare_sent_us;
    fbus_bulk_rx_t bulk;
} fbus_slot_t;

typedef struct {
    const hal_can_t *can; /* NULL: no finger bus, both slots empty */
    fbus_slot_t slot[FBUS_SLOTS];
    uint8_t power_mask;
    uint8_t counter;
    uint64_t next_state_us;
    /* grip-force loop */
    bool regulating;
    uint64_t regulated_us;
    float trim_n;
    float limit_n;
    bool force_request; /* limit_n waits for the supervisor */
    /* statistics */
    uint32_t tx_frames;
    uint32_t comm_faults;
    /* On an on-demand bus: the bus ticks until then, as something changed */
    bool wake;
    uint64_t awake_until_us;
    float woke_force_n; /* the jaw force the bus last woke for */
    /* On an on-demand bus: until then a step that takes no frame is a poll */
    uint64_t quiet_until_us;
    /* wsg_finger_bus_next_deadline_us(), worked out where what it follows
     * changes */
    uint64_t deadline_us;
    /* The bus's own quiet time (hal_can_quiet_until_us): a quiet step before
     * it does not poll, and the last such step (unpolled_us, 0: none) is
     * told to the bus before the next poll. */
    const uint64_t *bus_quiet_until_us;
    uint64_t unpolled_us;
} finger_bus_t;

/* What the bus hears from the core each step. */
typedef struct {
    uint64_t now_us;
    float position_mm;
    float motor_force_n; /* the axis' own (motor-current) force reading */
    uint8_t grip_state;
    bool holding; /* HOLDING with no motion running: the force loop may run */
    float grip_force_n;
    float force_max_n;
} fbus_input_t;

/* Power-on state; can may be NULL. Sets the controller's filters. */
void wsg_finger_bus_init(finger_bus_t *bus, const hal_can_t *can);
/* One control step: broadcast the jaw state when due, receive, supervise,
 * publish to fingers and compute the grip-force loop. False when the step
 * changed nothing in fingers (no bus, or a quiet poll). */
bool wsg_finger_bus_step(finger_bus_t *bus, wsg_fingers_t *fingers, const fbus_input_t *in);
/* On an on-demand bus a step that takes no frame changes nothing before the
 * next broadcast or supervision time, unless something woke the bus or the
 * force loop runs: supervise(), publish() and regulate() would find what
 * the last full step left. Such a step is a poll and nothing else (1 ms
 * steps while moving, of which one in ten broadcasts). What the bus alone
 * decides is in quiet_until_us (0 on a real bus, while the force loop runs
 * and after a TARE() between steps). */
static inline bool wsg_finger_bus_quiet(const finger_bus_t *bus, const wsg_fingers_t *fingers,
                                        uint64_t now_us, bool holding)
{
    return now_us < bus->quiet_until_us && !(holding && wsg_fingers_force_control(fingers));
}
/* A quiet step at an instant the bus says its poll would find nothing
 * (bus_quiet_until_us): the step only notes that it skipped the poll, and
 * is done (true): wsg_finger_bus_step() would do just that and return
 * false. Inline and without the step's input, for the device to ask first:
 * most steps while the jaws move. */
static inline bool wsg_finger_bus_skip_step(finger_bus_t *bus, const wsg_fingers_t *fingers,
                                            uint64_t now_us, bool holding)
{
    if (now_us < *bus->bus_quiet_until_us && wsg_finger_bus_quiet(bus, fingers, now_us, holding)) {
        bus->unpolled_us = now_us;
        return true;
    }
    return false;
}
/* The rest of a step that is not a quiet poll, from the frames its first
 * poll took (frames[0..count); NULL: none) on. Not inline: a quiet step,
 * nine in ten while the jaws move, stays a small function. */
void wsg_finger_bus_step_full(finger_bus_t *bus, wsg_fingers_t *fingers, const fbus_input_t *in,
                              const hal_can_frame_t *frames, unsigned count);
/* A real bus is supervised every 10 ms: its nodes run on their own and
 * power down without STATE. On an on-demand bus the nodes run when the
 * controller polls, so every step is a complete bus cycle: it ticks only
 * while something settles or the force loop runs. Inline: the device asks
 * at every step. */
static inline uint64_t wsg_finger_bus_next_deadline_us(const finger_bus_t *bus)
{
    return bus->deadline_us;
}
/* The fingers' readings follow the jaw force the bus broadcasts, and a
 * node's next reading may come only after the next broadcast (a DSA map
 * every 50 ms): a force that moved since the bus last woke for it wakes the
 * bus, which then ticks until the readings have followed. A bus left asleep
 * would keep them at the old force (the map of a grip FAST STOP released).
 * Inline: the device asks at every step. */
void wsg_finger_bus_wake_for_force(finger_bus_t *bus, float force_n);
static inline void wsg_finger_bus_follow_force(finger_bus_t *bus, float force_n)
{
    float moved = force_n - bus->woke_force_n;
    if (moved >= FBUS_FORCE_WAKE_N || moved <= -FBUS_FORCE_WAKE_N) {
        wsg_finger_bus_wake_for_force(bus, force_n);
    }
}
/* The force limit the loop asks the supervisor to drive with, once. */
bool wsg_finger_bus_take_force_request(finger_bus_t *bus, float *limit_n);
/* TARE() (index -1) or TARE(i): E_NOT_AVAILABLE without a connected FMF. */
wsg_status_t wsg_finger_bus_tare(finger_bus_t *bus, wsg_fingers_t *fingers, int index);

#endif
