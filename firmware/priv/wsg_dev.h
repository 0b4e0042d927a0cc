/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's private state and what the core's modules share. Never on a
 * port's include path: ports use include/wsg/ only. */
#ifndef WSG_DEV_H
#define WSG_DEV_H

#include "hal_log.h"
#include "priv/finger_bus.h"
#include "priv/motion_tuning.h"
#include "priv/timer.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_device.h"
#include "wsg/wsg_script.h"

typedef struct {
    wsg_motion_kind_t kind; /* the long operation running, or WSG_MOTION_NONE */
    wsg_owner_t *owner;     /* detached (NULL) when its connection closed */
    uint64_t started_us;
    float target_mm;
    float speed_mm_s;
    float force_n;
    bool stop_on_block;
    /* GRIP */
    bool grip_has_width;
    float grip_width_mm;
    float grip_pwt_mm;
    float grip_clt_mm;
    bool force_clear; /* the force read below contact level since the start */
    bool contact_seen;
    float contact_mm;
    /* HOME: the origin is taken; FIN waits for the force reading to settle */
    bool home_released;
    /* completion tracking */
    uint64_t condition_since_us; /* when the finishing condition first held */
    bool condition_holding;
    /* after ERR 29: how long the latched SF_BLOCKED_± has looked resolved */
    bool block_clearing;
    uint64_t block_clearing_since_us;
} dev_motion_t;

typedef struct {
    wsg_grip_state_t state;
    int8_t direction; /* -1: last grip closed on the part (inside), +1: outside */
    float force_n;    /* force of the last grip */
    float hold_mm;    /* where the jaws settled on the part */
    float clt_mm;
    bool monitored;         /* grip monitoring runs while HOLDING (forms with a width) */
    bool release_permitted; /* the last motion command was a GRIP (manual 2.2.4) */
    uint64_t weak_since_us;
    bool weak;
    uint32_t stats[3]; /* total grips, no part, part lost */
} dev_grip_t;

/* What the sense step read: the only place hardware readings enter. */
typedef struct {
    uint64_t now_us;
    hal_axis_status_t axis; /* axis.force_n: the motor's own estimate */
    float finger_force_n;   /* WSG-FMF measurement (0 without one) */
    float force_n;          /* the force the device acts on and reports */
    float temperature_c;
    bool force_control;  /* an FMF finger reports: its force is the one acted on */
    bool finger_faulted; /* a finger reports a fault */
    bool referenced;     /* dev->referenced when read */
} dev_sensed_t;

/* Velocity mode (a script's mc.speed(v)): the jaws driven at a speed until
 * something else takes the axis over; not an operation with an owner. */
typedef struct {
    bool active;
    float speed_mm_s; /* signed, positive opens; 0 holds the position */
} dev_velocity_t;

/* A user script's custom command channel (wsg_script.h): the IDs it claimed
 * (one bit each) and its request queue, a ring. */
typedef struct {
    uint32_t registered[8];
    wsg_script_request_t queue[WSG_SCRIPT_QUEUE_DEPTH];
    uint8_t head;
    uint8_t count;
    uint64_t last_host_id; /* the connection that sent the last binary frame */
    /* the driver of the connections that can be hosts, as the binary driver
     * noted it with its first frame (NULL before): the channel needs no
     * link to the driver that calls it */
    const wsg_proto_driver_t *host_driver;
} dev_script_t;

typedef struct {
    bool armed;
    char name[16]; /* a command name, upper case */
    wsg_status_t status;
} dev_injected_failure_t;

/* The command processor's state (a timing profile, docs/timing.md): when
 * it has served all it was given, whose work ends then, and the seeded
 * generator of its jitter. */
typedef struct {
    uint64_t rng;
    uint64_t free_at_us;
    uint64_t last_owner; /* the connection id of the work ending at free_at_us */
    uint32_t waiting;    /* requests held for it, all connections */
} dev_pace_t;

struct wsg_conn_impl;

typedef struct wsg_dev {
    wsg_config_t cfg; /* with the run-time settings applied */
    wsg_hal_t hal;
    dev_sensed_t sensed;
    bool sense_reacted;    /* the last wsg_sense_and_react() raised FAST STOP */
    bool axis_commanded;   /* the supervisor commanded the axis since the last sense */
    bool fingers_stepped;  /* this control step's finger bus step may have changed fingers */
    bool fingers_unsensed; /* fingers may have changed since the sense last read them */
    /* What the control step's tick counts from: the last control step, or,
     * while nothing ticks, the last sense. A query senses too, but must not
     * postpone the next step: queries faster than the tick starved it. */
    uint64_t tick_from_us;
    dev_motion_t motion;
    dev_velocity_t velocity;
    dev_grip_t grip;
    dev_script_t script;
    wsg_fingers_t fingers;
    finger_bus_t fbus;
    bool referenced;
    uint32_t latched_flags; /* flags the core sets and clears itself */
    uint32_t flags;         /* latched_flags plus those derived from the readings */
    dev_injected_failure_t injected_failure;
    dev_pace_t pace;
    wsg_timer_queue_t timers;    /* AUTOSEND subscriptions and other real deadlines */
    struct wsg_conn_impl *conns; /* open connections (intrusive list, oldest first) */
    struct wsg_conn_impl *conns_tail;
    const wsg_proto_driver_t *const *drivers; /* the port's, for auto-detection */
    size_t driver_count;
    uint64_t next_conn_id;
    wsg_snapshot_t snapshot;
    /* observer lists of caller-owned nodes: NULL unless attached */
    wsg_device_observers_t observers;
} wsg_dev_t;

_Static_assert(sizeof(wsg_dev_t) <= sizeof(wsg_device_t),
               "WSG_DEVICE_STORAGE_BYTES (wsg_opts.h) is too small for the device");

static inline wsg_dev_t *dev_of(wsg_device_t *dev)
{
    return (wsg_dev_t *)(void *)dev;
}

static inline const wsg_dev_t *dev_of_const(const wsg_device_t *dev)
{
    return (const wsg_dev_t *)(const void *)dev;
}

static inline wsg_device_t *dev_public(wsg_dev_t *dev)
{
    return (wsg_device_t *)(void *)dev;
}

/* sense.c: reads the clock, the axis and the temperature once; derives the
 * flag register. */
void wsg_sense(wsg_dev_t *dev);
/* wsg_sense(), then a severe fault raises FAST STOP. */
void wsg_sense_and_react(wsg_dev_t *dev);
/* wsg_sense_and_react() within a control step, which sets tick_from_us
 * when it ends. */
void wsg_step_sense_and_react(wsg_dev_t *dev);
/* wsg_step_sense_and_react() unless a sense now would read what the last
 * one read. */
void wsg_step_sense_and_react_if_changed(wsg_dev_t *dev);

/* flags.c: the register (pure) */
void wsg_flags_set(wsg_dev_t *dev, wsg_sysflag_t flag, bool on);
void wsg_flags_derive(wsg_dev_t *dev);

/* Inline: read at every control step. */
static inline bool wsg_flags_get(const wsg_dev_t *dev, wsg_sysflag_t flag)
{
    return (dev->flags & WSG_FLAG(flag)) != 0u;
}

/* How often the control must step now (µs), 0 when nothing changes by
 * itself. Inline: the sense and every deadline ask. */
static inline uint32_t wsg_device_tick_us(const wsg_dev_t *dev)
{
    if (dev->motion.kind != WSG_MOTION_NONE || dev->velocity.active ||
        wsg_flags_get(dev, SF_MOVING)) {
        return MOTION_TICK_US;
    }
    if (dev->grip.state == GS_HOLDING ||
        (dev->flags & (WSG_FLAG(SF_BLOCKED_MINUS) | WSG_FLAG(SF_BLOCKED_PLUS))) != 0u) {
        return HOLD_TICK_US;
    }
    return 0u;
}

/* Whether the simulation armed a failure for a command: a dispatch asks
 * before it calls wsg_device_take_injected_failure(), which rarely has one. */
static inline bool wsg_device_failure_armed(const wsg_dev_t *dev)
{
    return dev->injected_failure.armed;
}

/* A cause that raises FAST STOP by itself and blocks its acknowledge. */
static inline bool wsg_flags_severe_fault(const wsg_dev_t *dev)
{
    const dev_sensed_t *s = &dev->sensed;
    return s->axis.current_fault || s->axis.power_fault ||
           s->temperature_c >= dev->cfg.temp_fault_c;
}

/* pace.c: the command processor's slots. Reserves cost_us from when the
 * work before it ends (or now); returns the slot's end. *waited: it had to
 * wait; *behind_other: behind another owner's work. */
uint64_t wsg_pace_reserve(wsg_dev_t *dev, uint64_t now_us, uint32_t cost_us, uint64_t owner,
                          bool *behind_other);
/* A stream's timer fired under a timing profile, with `frames` frames due.
 * True: the processor is busy; the frames' slot is reserved and the timer
 * set for its start (*slot_reserved), send nothing now. False: send them
 * now (their cost is charged). */
bool wsg_pace_stream_waits(wsg_dev_t *dev, wsg_timer_t *timer, bool *slot_reserved, unsigned frames,
                           uint64_t owner, uint64_t now_us);

/* motion.c: the supervisor, the only writer of the axis */
void wsg_motion_drive(wsg_dev_t *dev, float target_mm, float speed_mm_s, float force_n);
void wsg_motion_halt(wsg_dev_t *dev, bool fast);
wsg_status_t wsg_motion_check_allowed(wsg_dev_t *dev, bool needs_reference);
/* A running MOVE that a new MOVE or velocity mode takes over ends here as
 * aborted (its owner hears E_CMD_ABORTED first); false when none runs, or
 * the configuration keeps the strict rejection (move_retarget = no). */
bool wsg_motion_supersede_move(wsg_dev_t *dev);
void wsg_motion_begin(wsg_dev_t *dev, wsg_owner_t *owner, wsg_motion_kind_t kind);
/* Ends the running motion now: its owner hears E_CMD_ABORTED before the
 * call returns (so before the reply to the command that ended it). */
void wsg_motion_abort(wsg_dev_t *dev);
/* FAST STOP: disables the drive, latches the flag, ends the motion (as
 * wsg_motion_abort). */
void wsg_motion_fast_stop(wsg_dev_t *dev, const char *why);
void wsg_motion_step(wsg_dev_t *dev);
/* Where a running GRIP's travel ends in "no part" (manual 2.2.6). */
float wsg_motion_grip_travel_limit(const dev_motion_t *m, int8_t direction);
void wsg_motion_apply_force_request(wsg_dev_t *dev);
void wsg_grip_set_state(wsg_dev_t *dev, wsg_grip_state_t state);
void wsg_grip_monitor_step(wsg_dev_t *dev);
void wsg_motion_block_watch_step(wsg_dev_t *dev);
/* Velocity mode: (re)commands the axis from dev->velocity and the force
 * limit; ends it (the axis is left to whatever ends it). */
void wsg_motion_velocity_drive(wsg_dev_t *dev);
void wsg_motion_velocity_end(wsg_dev_t *dev);

/* ---- for the protocol drivers and connections (firmware/ only) ------------ */

/* The outcome of a command on any connection (SF_CMD_FAILURE as the device
 * state reports it); protocol drivers call it from their dispatcher. */
void wsg_device_note_result(wsg_device_t *dev, wsg_status_t status);
/* Consumes an armed injected failure (wsg_inject.h) for this command name. */
bool wsg_device_take_injected_failure(wsg_device_t *dev, const char *name, wsg_status_t *status);
/* A device's 64-bit connection ids (logs, trace): never 0, never reused. */
uint64_t wsg_device_next_conn_id(wsg_device_t *dev);

#endif
