/* The virtual WSG device core: sessions, command dispatch, motion and grip
 * state machine, flags, statistics and AUTOSEND, driven by wsg_device_step().
 * All state lives in wsg_device_t; wsg_device_init() returns it to power-on. */
#ifndef WSG_DEVICE_H
#define WSG_DEVICE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gcl_linebuf.h"
#include "finger_bus.h"
#include "wsg_fingers.h"
#include "wsg_status.h"
#include "wsg_types.h"
#include "hal_axis.h"

/* Sessions the device serves at once. The host needs 128 TCP clients plus 16
 * UDP peers; a board port defines a smaller number for its RAM. */
#ifndef WSG_MAX_SESSIONS
#define WSG_MAX_SESSIONS 144
#endif

#define WSG_REPLY_MAX 1024 /* longest reply line (FDATA of two tactile fingers) */

typedef enum { WSG_TRANSPORT_STREAM, WSG_TRANSPORT_DATAGRAM } wsg_transport_t;

typedef enum {
    WSG_LINE_REPLY,    /* ACK/FIN/ERR/query answers: never dropped */
    WSG_LINE_AUTOSEND, /* @NAME=value: the port may drop it under back-pressure */
} wsg_line_kind_t;

typedef enum {
    WSG_CLOSE_ANNOUNCED, /* after BYE */
    WSG_CLOSE_DROPPED,   /* the connection went away without BYE */
    WSG_CLOSE_EXPIRED,   /* a datagram peer that the port forgot */
} wsg_close_reason_t;

/* How a session hands out its lines: one call per whole line, '\n' included. */
typedef struct {
    void (*write_line)(void *ctx, const char *line, size_t len, wsg_line_kind_t kind);
} wsg_session_io_t;

typedef struct {
    uint32_t interval_ms; /* 0: off */
    uint64_t next_due_us;
    bool use_delta;
    float delta;
    bool on_change;
    bool sent_once;
    float last_number;
    uint32_t last_bits;
    uint32_t missed; /* periods skipped because the device ran late */
} wsg_autosend_sub_t;

typedef struct {
    bool in_use;
    uint8_t index;
    uint64_t generation; /* tells a reused slot from its previous owner; never wraps in practice */
    wsg_transport_t transport;
    const wsg_session_io_t *io;
    void *io_ctx;
    gcl_linebuf_t input;
    bool verbose;
    float pwt_mm;
    float clt_mm;
    bool bye_received;
    bool cmd_failed; /* SF_CMD_FAILURE as this session sees it: its last command failed */
    wsg_autosend_sub_t autosend[AS_COUNT];
    uint32_t lines_in;
    uint32_t lines_out;
} wsg_session_t;

typedef enum {
    MOTION_NONE,
    MOTION_HOME,
    MOTION_MOVE,
    MOTION_GRIP,
    MOTION_RELEASE
} wsg_motion_kind_t;

typedef struct {
    wsg_motion_kind_t kind; /* the long command running, or MOTION_NONE */
    uint8_t owner_index;
    uint64_t owner_generation;
    uint64_t started_us;
    float target_mm;
    float speed_mm_s;
    float force_n;
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
    bool abort_requested;
    wsg_status_t abort_status;
    /* after ERR 29: how long the latched SF_BLOCKED_± has looked resolved */
    bool block_clearing;
    uint64_t block_clearing_since_us;
} wsg_motion_t;

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
} wsg_grip_t;

/* Optional observers, used by the host for tracing, recording and coverage. */
typedef struct {
    void (*line_in)(void *ctx, const wsg_session_t *s, const char *line, size_t len);
    void (*line_out)(void *ctx, const wsg_session_t *s, const char *line, size_t len);
    void (*grip_state_changed)(void *ctx, wsg_grip_state_t from, wsg_grip_state_t to);
    void (*command_done)(void *ctx, const wsg_session_t *s, const char *name, unsigned form,
                         unsigned argc, wsg_status_t status);
    /* input the manual does not allow but the device accepted */
    void (*tolerated)(void *ctx, const wsg_session_t *s, const char *name, const char *what);
} wsg_device_hooks_t;

/* Fault injection: the next command of this name fails with this status
 * before it runs (set by the simulation's control channel). */
typedef struct {
    bool armed;
    char name[GCL_NAME_MAX + 1];
    wsg_status_t status;
} wsg_injected_failure_t;

typedef struct wsg_device {
    wsg_session_t sessions[WSG_MAX_SESSIONS];
    uint64_t next_generation;
    wsg_motion_t motion;
    wsg_grip_t grip;
    wsg_fingers_t fingers;
    finger_bus_t fbus; /* the finger bus behind the slots (survives a reset) */
    bool referenced;
    uint32_t latched_flags; /* flags the core sets and clears itself */
    uint32_t flags;         /* latched_flags plus those derived from the hardware */
    hal_axis_status_t axis; /* last reading */
    float temperature_c;
    uint64_t now_us;
    wsg_injected_failure_t injected_failure;
    const wsg_device_hooks_t *hooks;
    void *hooks_ctx;
} wsg_device_t;

/* Power-on state. Hooks survive a reset. */
void wsg_device_init(wsg_device_t *dev);
void wsg_device_set_hooks(wsg_device_t *dev, const wsg_device_hooks_t *hooks, void *ctx);

/* Runs the control step: reads the hardware, advances motion and grip
 * monitoring, emits final replies and due AUTOSEND lines. */
void wsg_device_step(wsg_device_t *dev);

/* The latest time at which wsg_device_step() must run again. */
uint64_t wsg_device_next_deadline_us(const wsg_device_t *dev);

/* Sessions. open returns NULL when all slots are taken. */
wsg_session_t *wsg_session_open(wsg_device_t *dev, wsg_transport_t transport,
                                const wsg_session_io_t *io, void *io_ctx);
void wsg_session_input(wsg_device_t *dev, wsg_session_t *s, const uint8_t *bytes, size_t len);
/* A datagram ends any line it left open (UDP clients may omit the '\n'). */
void wsg_session_end_datagram(wsg_device_t *dev, wsg_session_t *s);
/* True once BYE was answered: the port closes the connection after flushing. */
bool wsg_session_wants_close(const wsg_session_t *s);
void wsg_session_close(wsg_device_t *dev, wsg_session_t *s, wsg_close_reason_t reason);
bool wsg_session_has_autosend(const wsg_session_t *s);

/* Raises a FAST STOP as FASTSTOP() does (also used by fault handling). */
void wsg_device_fast_stop(wsg_device_t *dev, const char *why);

/* Connects the finger bus (NULL: none, both slots empty); the port calls it
 * once after wsg_device_init(). */
void wsg_device_attach_can(wsg_device_t *dev, const hal_can_t *can);

/* Fault injection: the next well-formed command called `name` (upper case)
 * answers ERR <name> <status> without running. A reset disarms it. */
void wsg_device_inject_failure(wsg_device_t *dev, const char *name, wsg_status_t status);

#endif
