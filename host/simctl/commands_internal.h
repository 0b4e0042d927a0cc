/* SPDX-License-Identifier: BSD-3-Clause */
/* What the control command handlers share. */
#ifndef SIM_COMMANDS_INTERNAL_H
#define SIM_COMMANDS_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include <cJSON.h>

#include "simctl_sim.h"
#include "wsg/gcl_parse.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

typedef struct {
    simctl_t *ctl;
    const gcl_command_t *cmd;
    const char *line; /* the command as sent (a long text argument is read from it) */
    size_t line_len;
    struct gripper *gripper; /* the device the command addresses */
    unsigned *selected;      /* the channel's DEVICE= selection; NULL: a scenario */
    char *reply;             /* malloc'd reply; NULL: "ACK NAME" */
    char why[192];
    wsg_status_t failed; /* the status sc_fail() set last */
    bool close;
    bool deferred;   /* a STEP started: the reply comes when it has run */
    bool check_only; /* only check the arguments (a scenario at start-up) */
} simctl_ctx_t;

typedef wsg_status_t (*simctl_handler_t)(simctl_ctx_t *ctx);

typedef struct {
    const char *name;
    unsigned forms; /* gcl_form_t mask */
    unsigned min_args;
    unsigned max_args;
    simctl_handler_t handler;
    const char *usage;
    bool in_scenario; /* a scenario may run it */
} simctl_entry_t;

/* simctl/commands_ctx.c: what a handler does with its context. */

/* Sets the reason of an ERR reply and returns status. */
wsg_status_t sc_fail(simctl_ctx_t *ctx, wsg_status_t status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Sets the reply line ("NAME=value" is up to the handler). */
void sc_reply(simctl_ctx_t *ctx, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* NAME=<text>; takes ownership of text (from cJSON or asprintf). */
void sc_reply_owned(simctl_ctx_t *ctx, char *text);
/* NAME=<compact JSON of json>; takes ownership of json. */
void sc_reply_json(simctl_ctx_t *ctx, cJSON *json);

/* Argument i as a number / text (quoted string or bare word); false (with
 * the reason and ctx->failed set) when it has another type. */
bool sc_number(simctl_ctx_t *ctx, unsigned i, double *out);
bool sc_text(simctl_ctx_t *ctx, unsigned i, const char **out);
bool sc_has_arg(const simctl_ctx_t *ctx, unsigned i);
/* NAME("text") with text of any length the line holds: the text into out
 * (when not NULL); false when the line has another shape. */
bool sc_quoted_call(const char *line, size_t len, char *out, size_t cap);
/* The one argument of a command that takes a long text (SCRIPT_RUN's host
 * path, not only GCL's 31 characters): the quoted text as sent, else the
 * argument as sc_text() reads it. */
bool sc_long_text(simctl_ctx_t *ctx, char *out, size_t cap);
/* Argument i as an integer min..max (what names it in the reason): false with
 * ERR 24 when it is not a number, ERR 28 when it has a fraction or is out of
 * range. Never converts an out-of-range double. */
bool sc_integer(simctl_ctx_t *ctx, unsigned i, const char *what, int64_t min, int64_t max,
                int64_t *out);
/* Argument i as a session id of an open session; NULL (reason set) if not.
 * While only checking, any well-formed id passes (returns NULL, no failure). */
wsg_conn_t *sc_session(simctl_ctx_t *ctx, unsigned i);
/* True while the handler only checks its arguments: it must change nothing
 * and return E_SUCCESS once they are valid. */
bool sc_checking(const simctl_ctx_t *ctx);
/* The device noticed a change of the world at once (a control step now). */
void sc_world_changed(simctl_ctx_t *ctx);
/* simctl/commands_clock.c */
wsg_status_t sc_pause(simctl_ctx_t *ctx);
wsg_status_t sc_resume(simctl_ctx_t *ctx);
wsg_status_t sc_step(simctl_ctx_t *ctx);
wsg_status_t sc_run_until_done(simctl_ctx_t *ctx);
wsg_status_t sc_scale(simctl_ctx_t *ctx);
wsg_status_t sc_simtime(simctl_ctx_t *ctx);
wsg_status_t sc_timing(simctl_ctx_t *ctx);

/* simctl/commands_world.c */
wsg_status_t sc_part(simctl_ctx_t *ctx);
wsg_status_t sc_part_remove(simctl_ctx_t *ctx);
wsg_status_t sc_part_slip(simctl_ctx_t *ctx);
wsg_status_t sc_obstacle(simctl_ctx_t *ctx);
wsg_status_t sc_obstacle_remove(simctl_ctx_t *ctx);
wsg_status_t sc_ambient(simctl_ctx_t *ctx);

/* simctl/commands_physics.c */
wsg_status_t sc_physics(simctl_ctx_t *ctx);
wsg_status_t sc_bodies(simctl_ctx_t *ctx);
wsg_status_t sc_body(simctl_ctx_t *ctx);
wsg_status_t sc_contacts(simctl_ctx_t *ctx);
wsg_status_t sc_place(simctl_ctx_t *ctx);
wsg_status_t sc_lift(simctl_ctx_t *ctx);
wsg_status_t sc_pull(simctl_ctx_t *ctx);
wsg_status_t sc_mass(simctl_ctx_t *ctx);
wsg_status_t sc_friction(simctl_ctx_t *ctx);

/* simctl/commands_fault.c */
wsg_status_t sc_fault(simctl_ctx_t *ctx);
wsg_status_t sc_clear(simctl_ctx_t *ctx);
wsg_status_t sc_faults(simctl_ctx_t *ctx);
/* The active injected faults of the device as a JSON array (FAULTS?, and
 * the "faults" of STATE?). */
cJSON *sc_faults_json(simctl_t *ctl, struct gripper *g);
wsg_status_t sc_delay(simctl_ctx_t *ctx);
wsg_status_t sc_failnext(simctl_ctx_t *ctx);
wsg_status_t sc_cut(simctl_ctx_t *ctx);

/* simctl/commands_net.c */
wsg_status_t sc_net(simctl_ctx_t *ctx);

/* simctl/commands_state.c */
wsg_status_t sc_state(simctl_ctx_t *ctx);
wsg_status_t sc_sessions(simctl_ctx_t *ctx);
wsg_status_t sc_reset(simctl_ctx_t *ctx);
wsg_status_t sc_coverage(simctl_ctx_t *ctx);
wsg_status_t sc_coverage_reset(simctl_ctx_t *ctx);
wsg_status_t sc_driver(simctl_ctx_t *ctx);
wsg_status_t sc_log(simctl_ctx_t *ctx);
wsg_status_t sc_device(simctl_ctx_t *ctx);
wsg_status_t sc_devices(simctl_ctx_t *ctx);
wsg_status_t sc_bye(simctl_ctx_t *ctx);

/* simctl/commands_script.c */
wsg_status_t sc_script_run(simctl_ctx_t *ctx);
wsg_status_t sc_script_stop(simctl_ctx_t *ctx);
wsg_status_t sc_script(simctl_ctx_t *ctx);

#endif
