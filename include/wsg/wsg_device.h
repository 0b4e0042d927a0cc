/* SPDX-License-Identifier: BSD-3-Clause */
/* One virtual WSG device: its life cycle, the operations every protocol
 * driver calls, the read-only snapshot and the observers.
 *
 * The port allocates the storage (static on a board, a pool or an array on
 * the host); the firmware never allocates. The layout is private: the
 * storage is a byte array of a size fixed by wsg_opts.h, FreeRTOS
 * StaticTask_t style, and the core checks at compile time that it fits. */
#ifndef WSG_DEVICE_H
#define WSG_DEVICE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal.h"
#include "wsg_config.h"
#include "wsg_fingers.h"
#include "wsg_opts.h"
#include "wsg_status.h"
#include "wsg_types.h"

#define WSG_ALIGNED _Alignas(8)

typedef struct wsg_device {
    WSG_ALIGNED unsigned char storage[WSG_DEVICE_STORAGE_BYTES];
} wsg_device_t;

/* ---- life cycle ---------------------------------------------------------- */

/* Once: binds the configuration (copied) and the hardware, then powers on. */
void wsg_device_init(wsg_device_t *dev, const wsg_config_t *cfg, const wsg_hal_t *hal);
/* Power-on state again: keeps configuration, hardware and observers; every
 * connection must have been closed first. Run-time settings go back to cfg. */
void wsg_device_reset(wsg_device_t *dev, const wsg_config_t *cfg);
/* One control step: wsg_sense (clock, axis, temperature), supervise the motion,
 * monitor the grip, then run every timer that is due. */
void wsg_device_step(wsg_device_t *dev);
/* The sense step alone: reads the hardware now, so that a command between
 * steps acts on the newest reading; a severe fault raises FAST STOP here. */
void wsg_device_sense(wsg_device_t *dev);
/* wsg_device_sense() unless the last sense was at this same instant and
 * raised nothing: for a caller that knows nothing acted on the device since
 * (a protocol driver between two queries of one input), as then the same
 * instant gives the same reading. */
void wsg_device_sense_if_moved_on(wsg_device_t *dev);
/* When wsg_device_step() must run next; UINT64_MAX when nothing can change
 * without an outside event (a command, a control-channel change). */
uint64_t wsg_device_next_deadline_us(const wsg_device_t *dev);

/* ---- coasting ------------------------------------------------------------- */

/* While a motion runs clear of everything, most control steps change nothing
 * but the readings they store. Asked right after a control step,
 * wsg_device_coast() says how far that holds: a step at an instant before
 * until_us whose readings are within the envelope (wsg_coast_within())
 * would change nothing else, and would make the next step due at
 * wsg_coast_next_us(). A port that reads the hardware more cheaply than a
 * step (a simulated world) may leave such steps out. After the last one it
 * left out it calls wsg_device_coasted(), then runs the step of the instant
 * that follows before anything else (input, a query, the snapshot's
 * readers) meets the device: only a step stores the readings. */
typedef struct {
    uint64_t until_us;
    uint64_t due_us; /* the device's deadlines other than its tick (timers, the bus) */
    uint32_t step_us;
    float position_above_mm; /* the position strictly between these */
    float position_below_mm;
    float force_below_n;
    float temperature_below_c;
} wsg_coast_t;

/* False when no step may be left out (*coast is then of no use). */
bool wsg_device_coast(const wsg_device_t *dev, wsg_coast_t *coast);
/* The port left out the steps up to last_us, the last of them. */
void wsg_device_coasted(wsg_device_t *dev, uint64_t last_us);

/* When the step after one left out at left_out_us is due: a tick later,
 * or at the device's next other deadline if that comes first. */
static inline uint64_t wsg_coast_next_us(const wsg_coast_t *c, uint64_t left_out_us)
{
    uint64_t tick = left_out_us + c->step_us;
    return tick < c->due_us ? tick : c->due_us;
}

/* Whether readings taken at an instant before until_us are within the
 * envelope: the profile running and not blocked, no fault, position, force
 * and temperature inside their bounds. Inline: the port asks at each
 * instant it may leave out. */
static inline bool wsg_coast_within(const wsg_coast_t *c, const hal_axis_status_t *axis,
                                    float temperature_c)
{
    return axis->profile_active && axis->blocked == 0 && !axis->power_fault &&
           !axis->current_fault && axis->position_mm > c->position_above_mm &&
           axis->position_mm < c->position_below_mm && axis->force_n < c->force_below_n &&
           temperature_c < c->temperature_below_c;
}

/* ---- owners and completion events ---------------------------------------- */

typedef enum { WSG_OP_HOME, WSG_OP_MOVE, WSG_OP_GRIP, WSG_OP_RELEASE, WSG_OP_COUNT } wsg_op_t;

/* Who started a long operation: embedded in a connection (or a web
 * request). Its done() hears the final status exactly once; detaching it
 * (on close) means no completion can ever reach it, or a later owner in the
 * same storage. */
typedef struct wsg_owner {
    void (*done)(struct wsg_owner *owner, wsg_op_t op, wsg_status_t status);
} wsg_owner_t;

void wsg_device_detach(wsg_device_t *dev, const wsg_owner_t *owner);
/* True while this owner's operation runs. */
bool wsg_device_owns_motion(const wsg_device_t *dev, const wsg_owner_t *owner);

/* ---- operations ------------------------------------------------------------
 * Long operations return E_SUCCESS when started (the driver acknowledges) or
 * the immediate error; the final status arrives through owner->done() from
 * a later wsg_device_step(), never from within the call that started it.
 * A running operation that a new one ends (a MOVE superseding a MOVE, a
 * pending STOP) reports to its owner before the new one starts. */

typedef enum { WSG_HOME_DEFAULT, WSG_HOME_POSITIVE, WSG_HOME_NEGATIVE } wsg_home_dir_t;

typedef struct {
    wsg_home_dir_t direction;
} wsg_home_args_t;

typedef struct {
    float position_mm; /* absolute, or a distance when relative */
    float speed_mm_s;
    bool relative;
    bool stop_on_block; /* binary protocol: a block ends the move as success */
} wsg_move_args_t;

typedef struct {
    float force_n;  /* the binary protocol passes the force limit setting */
    bool has_width; /* a nominal part width: part detection and monitoring */
    float width_mm;
    float speed_mm_s;
    float pwt_mm; /* part width tolerance */
    float clt_mm; /* clamping travel */
} wsg_grip_args_t;

typedef struct {
    float distance_mm; /* pull-back distance, away from the part */
    float speed_mm_s;
    bool to_width; /* binary protocol: open to width_mm instead */
    float width_mm;
} wsg_release_args_t;

wsg_status_t wsg_op_home(wsg_device_t *dev, wsg_owner_t *owner, const wsg_home_args_t *args);
wsg_status_t wsg_op_move(wsg_device_t *dev, wsg_owner_t *owner, const wsg_move_args_t *args);
wsg_status_t wsg_op_grip(wsg_device_t *dev, wsg_owner_t *owner, const wsg_grip_args_t *args);
wsg_status_t wsg_op_release(wsg_device_t *dev, wsg_owner_t *owner, const wsg_release_args_t *args);
/* Velocity mode (a script's mc.speed(v), docs/scripting.md): drives the jaws
 * at v mm/s, positive opening, |v| clamped to the model's maximum, 0 holding
 * the position, with the force limit setting (a new limit applies at once),
 * pushing on whatever stops them (SF_BLOCKED_± while they push) or stopping
 * at a soft limit. It lasts until STOP, FAST STOP, any motion or a new
 * velocity. It takes over a running MOVE as a new MOVE does: the MOVE ends
 * first, its owner hearing E_CMD_ABORTED (unless move_retarget is off).
 * E_NOT_INITIALIZED, E_ACCESS_DENIED (FAST STOP), E_ALREADY_RUNNING (HOME,
 * GRIP or RELEASE runs, or a MOVE that may not be taken over),
 * E_INVALID_PARAMETER (NaN). */
wsg_status_t wsg_op_velocity(wsg_device_t *dev, float speed_mm_s);
/* True in velocity mode; *speed_mm_s (may be NULL) its commanded speed. */
bool wsg_device_velocity_mode(const wsg_device_t *dev, float *speed_mm_s);
/* Manual 3.2.1: ends a movement (its owner hears E_CMD_ABORTED); a grip
 * result (HOLDING, NO PART, PART LOST) stays. */
wsg_status_t wsg_op_stop(wsg_device_t *dev);
/* Manual 3.2.2: why goes to the log. */
wsg_status_t wsg_op_fast_stop(wsg_device_t *dev, const char *why);
/* E_ACCESS_DENIED while a severe fault lasts. */
wsg_status_t wsg_op_fsack(wsg_device_t *dev);
/* finger -1: every force finger. E_INDEX_OUT_OF_BOUNDS, E_NOT_AVAILABLE. */
wsg_status_t wsg_op_tare(wsg_device_t *dev, int finger);
wsg_status_t wsg_op_reset_grip_stats(wsg_device_t *dev);

/* Settings: device state shared by every protocol, validated here. */
typedef enum {
    WSG_SET_ACCEL,               /* mm/s^2 */
    WSG_SET_FORCE_LIMIT,         /* N: default grip force */
    WSG_SET_SOFT_LIMITS,         /* 0/1 */
    WSG_SET_SOFT_MINUS,          /* mm */
    WSG_SET_SOFT_PLUS,           /* mm */
    WSG_SET_OVERDRIVE,           /* 0/1 */
    WSG_SET_DEFAULT_SPEED,       /* mm/s */
    WSG_SET_DEFAULT_PWT,         /* mm */
    WSG_SET_DEFAULT_CLT,         /* mm */
    WSG_SET_DEFAULT_PULLBACK,    /* mm: RELEASE's default distance */
    WSG_SET_DISCONNECT_FASTSTOP, /* 0/1: a dropped TCP connection raises FAST STOP */
    WSG_SET_BINARY_CRC_CHECK,    /* 0/1: binary requests' checksums are checked */
    WSG_SET_COUNT
} wsg_setting_t;

/* How a setting is held and checked: the one description wsg_op_set() works
 * from, and that a front end's table of names (host/config/settings_table.c)
 * derives units, ranges and fields from. */
typedef enum {
    WSG_SETTING_SWITCH,     /* on/off, any value: 0 is off */
    WSG_SETTING_ACCEL,      /* wsg_config_accel_ok() */
    WSG_SETTING_FORCE,      /* wsg_config_force_ok(): force_min_n..wsg_config_force_max() */
    WSG_SETTING_SPEED,      /* wsg_config_speed_ok() */
    WSG_SETTING_LENGTH,     /* wsg_config_length_ok(): 0..stroke_mm */
    WSG_SETTING_SOFT_LIMIT, /* a position: the configuration stays valid (wsg_config_check()) */
} wsg_setting_check_t;

typedef struct {
    const char *unit; /* "mm", "mm/s", "mm/s^2", "N"; "" for a switch */
    wsg_setting_check_t check;
    unsigned offset; /* of its field in wsg_config_t: a float, or a bool for a switch */
    bool inverted;   /* a switch whose field holds the opposite (bin_crc_unchecked) */
} wsg_setting_info_t;

/* The description of a setting; NULL for no such setting. */
const wsg_setting_info_t *wsg_setting_info(wsg_setting_t which);
/* A setting's value in cfg (a switch: 1 on, 0 off); 0 for no such setting. */
float wsg_config_setting_get(const wsg_config_t *cfg, wsg_setting_t which);
/* Stores value in cfg's field without a check (a switch: on unless 0), for
 * a configuration being made before a device runs it; nothing for no such
 * setting. A running device's settings change through wsg_op_set(). */
void wsg_config_setting_put(wsg_config_t *cfg, wsg_setting_t which, float value);

/* Checks value as wsg_setting_info() describes and sets it: E_RANGE_ERROR
 * outside its range, E_FEATURE_NOT_SUPPORTED for overdrive on a model
 * without it, E_INVALID_PARAMETER for no such setting. */
wsg_status_t wsg_op_set(wsg_device_t *dev, wsg_setting_t which, float value);
/* The device tag (descriptor string): len bytes, no terminating NUL needed.
 * The one check of every front end: E_RANGE_ERROR when longer than
 * WSG_CONFIG_STRING_MAX - 1 characters, E_INVALID_PARAMETER for a byte
 * wsg_config_text_char_ok() refuses (CR, LF, NUL, '"', beyond ASCII); the
 * tag keeps its value on an error. */
wsg_status_t wsg_op_set_tag(wsg_device_t *dev, const char *tag, size_t len);
/* The same checks on a configuration that no device runs (a copy of the
 * one in force, say): the value stored when the checks pass, cfg left as
 * it was when not. A front end checks a set of settings as a whole this
 * way, in the order it would apply them, before it applies any. */
wsg_status_t wsg_config_setting_set(wsg_config_t *cfg, wsg_setting_t which, float value);
wsg_status_t wsg_config_set_tag(wsg_config_t *cfg, const char *tag, size_t len);

/* ---- the snapshot ---------------------------------------------------------- */

typedef enum {
    WSG_MOTION_NONE,
    WSG_MOTION_HOME,
    WSG_MOTION_MOVE,
    WSG_MOTION_GRIP,
    WSG_MOTION_RELEASE
} wsg_motion_kind_t;

typedef struct {
    uint64_t now_us; /* when it was sensed */
    /* axis */
    float position_mm;
    float speed_mm_s;     /* >= 0 */
    float velocity_mm_s;  /* signed */
    float force_n;        /* what FORCE? reports (wsg_snapshot_force policy) */
    float motor_force_n;  /* the motor current's estimate */
    float finger_force_n; /* the WSG-FMF measurement; 0 without one */
    int8_t blocked;
    bool profile_active;
    bool current_fault, power_fault;
    bool referenced;
    float temperature_c;
    uint32_t flags; /* Appendix B, SF_CMD_FAILURE as the device last saw it */
    /* motion in progress */
    wsg_motion_kind_t motion;
    const wsg_owner_t *motion_owner;
    uint64_t motion_started_us;
    float motion_target_mm, motion_speed_mm_s, motion_force_n;
    /* grip */
    wsg_grip_state_t grip_state;
    int8_t grip_direction;
    float grip_force_n, grip_hold_mm, grip_clt_mm;
    bool grip_monitored, release_permitted;
    uint32_t grip_stats[3]; /* total, no part, part lost */
    /* fingers, configuration (with run-time settings applied) */
    const wsg_fingers_t *fingers;
    const wsg_config_t *config;
    /* fault injection */
    bool injected_armed;
    const char *injected_name;
    wsg_status_t injected_status;
} wsg_snapshot_t;

/* Fills the device's snapshot from its last sense and returns it; valid
 * until the next call on the device. */
const wsg_snapshot_t *wsg_device_snapshot(wsg_device_t *dev);

/* One value of the last sense, as the snapshot has it, without filling the
 * snapshot: for a query that answers with one number. */
typedef enum {
    WSG_READING_POSITION,    /* snapshot.position_mm */
    WSG_READING_SPEED,       /* snapshot.speed_mm_s */
    WSG_READING_FORCE,       /* snapshot.force_n */
    WSG_READING_TEMPERATURE, /* snapshot.temperature_c */
} wsg_reading_t;
float wsg_device_reading(const wsg_device_t *dev, wsg_reading_t which);
/* snapshot.flags, without filling the snapshot: for what samples the flags
 * at every step (the coverage report). */
uint32_t wsg_device_flags(const wsg_device_t *dev);
/* snapshot.motion and snapshot.motion_started_us, without filling the
 * snapshot: for what watches for the end of a motion at every step. */
wsg_motion_kind_t wsg_device_motion(const wsg_device_t *dev, uint64_t *started_us);

/* ---- observers ------------------------------------------------------------- */

/* Caller-owned list nodes, as wsg_conn_observer_t (wsg_conn.h): attached
 * only when asked for (coverage); called in the order they were added; a
 * device without observers pays one pointer test per event. */
typedef struct wsg_device_observer {
    void (*grip_state_changed)(void *ctx, wsg_grip_state_t from, wsg_grip_state_t to);
    void *ctx;
    struct wsg_device_observer *next; /* the core's */
} wsg_device_observer_t;

void wsg_device_add_observer(wsg_device_t *dev, wsg_device_observer_t *node);
void wsg_device_remove_observer(wsg_device_t *dev, wsg_device_observer_t *node);

/* Every observer list of the device (device, connection and GCL observers),
 * taken away for a while and given back: what happens meanwhile goes
 * unobserved (a power cycle's closures), whoever observes. */
typedef struct {
    struct wsg_device_observer *device;
    struct wsg_conn_observer *conn;
    struct wsg_gcl_observer *gcl;
    unsigned conn_readers; /* connection observers with a read() hook */
} wsg_device_observers_t;

void wsg_device_take_observers(wsg_device_t *dev, wsg_device_observers_t *taken);
void wsg_device_give_observers(wsg_device_t *dev, const wsg_device_observers_t *taken);

#endif
