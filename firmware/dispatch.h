/* The command table and what handlers share: their context and the
 * argument converters that map GCL tokens to typed values. */
#ifndef DISPATCH_H
#define DISPATCH_H

#include "gcl_parse.h"
#include "wsg_internal.h"

typedef struct {
    wsg_device_t *dev;
    wsg_session_t *session;
    const gcl_command_t *cmd;
} cmd_ctx_t;

typedef wsg_status_t (*cmd_handler_t)(cmd_ctx_t *ctx);

typedef struct {
    const char *name;
    unsigned forms;    /* gcl_form_t mask */
    unsigned min_args; /* for GCL_FORM_CALL */
    unsigned max_args;
    cmd_handler_t handler;
} cmd_entry_t;

const cmd_entry_t *dispatch_find(const char *name);
/* The command table in order (coverage reports enumerate it). */
unsigned dispatch_count(void);
const cmd_entry_t *dispatch_at(unsigned i);

/* Argument converters: E_SUCCESS, E_INVALID_PARAMETER (wrong type) or
 * E_RANGE_ERROR (a bool that is neither 0 nor 1). */
wsg_status_t arg_float(const cmd_ctx_t *ctx, unsigned i, float *out);
wsg_status_t arg_int(const cmd_ctx_t *ctx, unsigned i, int32_t *out);
wsg_status_t arg_bool(const cmd_ctx_t *ctx, unsigned i, bool *out);
/* A quoted string, or (tolerated) a bare word. */
wsg_status_t arg_text(const cmd_ctx_t *ctx, unsigned i, const char **out);
bool in_range(float value, float min, float max);
/* Reports input the manual does not allow but the device accepts. */
void note_tolerated(const cmd_ctx_t *ctx, const char *what);

/* Reply helpers */
void reply_ack(cmd_ctx_t *ctx);
void reply_float(cmd_ctx_t *ctx, float value);
void reply_int(cmd_ctx_t *ctx, int32_t value);
void reply_quoted(cmd_ctx_t *ctx, const char *value);

/* Handlers */
wsg_status_t cmd_verbose(cmd_ctx_t *ctx);
wsg_status_t cmd_bye(cmd_ctx_t *ctx);
wsg_status_t cmd_home(cmd_ctx_t *ctx);
wsg_status_t cmd_move(cmd_ctx_t *ctx);
wsg_status_t cmd_grip(cmd_ctx_t *ctx);
wsg_status_t cmd_release(cmd_ctx_t *ctx);
wsg_status_t cmd_stop(cmd_ctx_t *ctx);
wsg_status_t cmd_faststop(cmd_ctx_t *ctx);
wsg_status_t cmd_fsack(cmd_ctx_t *ctx);
wsg_status_t cmd_pwt(cmd_ctx_t *ctx);
wsg_status_t cmd_clt(cmd_ctx_t *ctx);
wsg_status_t cmd_pos(cmd_ctx_t *ctx);
wsg_status_t cmd_speed(cmd_ctx_t *ctx);
wsg_status_t cmd_force(cmd_ctx_t *ctx);
wsg_status_t cmd_gripstate(cmd_ctx_t *ctx);
wsg_status_t cmd_gripstats(cmd_ctx_t *ctx);
wsg_status_t cmd_sysflags(cmd_ctx_t *ctx);
wsg_status_t cmd_temp(cmd_ctx_t *ctx);
wsg_status_t cmd_devtype(cmd_ctx_t *ctx);
wsg_status_t cmd_version(cmd_ctx_t *ctx);
wsg_status_t cmd_sn(cmd_ctx_t *ctx);
wsg_status_t cmd_tag(cmd_ctx_t *ctx);
wsg_status_t cmd_autosend(cmd_ctx_t *ctx);
wsg_status_t cmd_tare(cmd_ctx_t *ctx);
wsg_status_t cmd_fdata(cmd_ctx_t *ctx);
wsg_status_t cmd_ftype(cmd_ctx_t *ctx);
wsg_status_t cmd_fflags(cmd_ctx_t *ctx);

#endif
