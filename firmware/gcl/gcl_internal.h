/* SPDX-License-Identifier: BSD-3-Clause */
/* The GCL driver's own declarations: its per-connection state, the command
 * table, the handlers' context, argument converters and reply formatting.
 * Nothing outside firmware/gcl includes this. */
#ifndef GCL_INTERNAL_H
#define GCL_INTERNAL_H

#include "wsg/gcl_linebuf.h"
#include "wsg/gcl_parse.h"
#include "priv/conn.h"
#include "wsg/wsg_textbuf.h"
#include "priv/timer.h"
#include "wsg/wsg_gcl.h"

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
} gcl_autosend_sub_t;

#define GCL_QUERY_LINE_MAX 24
#define GCL_FLOAT_TEXT_KEPT 11u /* "-12345.678" and shorter: any position, speed, force */

/* A GCL connection's state, inside its wsg_conn_t. */
typedef struct {
    conn_t *conn;
    gcl_linebuf_t input;
    bool verbose;
    float pwt_mm;
    float clt_mm;
    bool cmd_failed; /* SF_CMD_FAILURE as this connection sees it: its last command failed */
    gcl_autosend_sub_t autosend[AS_COUNT];
    wsg_timer_t autosend_timer; /* due at the earliest subscription */
    uint32_t lines_in;
    uint32_t lines_out;
    const struct cmd_entry *last_command; /* looked up first: pollers repeat one command */
    /* Within one input call, the lines since the last sense ran only queries:
     * nothing outside the driver runs between them, so at the same instant
     * the device reads the same (wsg_device_sense_if_moved_on). */
    bool in_input;
    bool quiet_since_sense;
    /* The last plain query line (NAME?) as received, and its command: a poller
     * repeats one line, and a parse depends on the line's bytes alone. */
    char query_line[GCL_QUERY_LINE_MAX];
    uint8_t query_line_len; /* 0: none yet */
    const struct cmd_entry *query_entry;
    char query_name[GCL_NAME_MAX + 1]; /* its command's name, NUL-padded */
    uint8_t query_name_len;
    /* The last float reply's text and its value's bits: a poller reads one
     * value again and again while the gripper rests (wsg_reply_float). */
    uint8_t float_len; /* 0: none kept */
    char float_text[GCL_FLOAT_TEXT_KEPT];
    uint32_t float_bits;
} gcl_conn_t;

_Static_assert(sizeof(gcl_conn_t) <= CONN_PROTO_BYTES,
               "WSG_CONN_STORAGE_BYTES (wsg_opts.h) is too small for a GCL connection");

static inline gcl_conn_t *gcl_of(wsg_conn_t *c)
{
    return (gcl_conn_t *)(void *)conn_of(c)->proto;
}

static inline const gcl_conn_t *gcl_of_const(const wsg_conn_t *c)
{
    return (const gcl_conn_t *)(const void *)conn_of_const(c)->proto;
}

static inline wsg_device_t *gcl_device(const gcl_conn_t *g)
{
    return dev_public(g->conn->dev);
}

/* The first GCL observer of the connection's device (a list), or NULL. */
static inline const wsg_gcl_observer_t *gcl_observers(const gcl_conn_t *g)
{
    return g->conn->dev->observers.gcl;
}

typedef struct {
    gcl_conn_t *gcl;
    wsg_device_t *dev;
    const gcl_command_t *cmd;
    size_t name_len; /* of cmd->name, for the replies that start with it */
} cmd_ctx_t;

typedef wsg_status_t (*cmd_handler_t)(cmd_ctx_t *ctx);

typedef struct cmd_entry {
    wsg_gcl_command_t info;
    cmd_handler_t handler;
} cmd_entry_t;

/* dispatch.c */
/* request_kind.c: the line's kind for the command processor */
wsg_request_kind_t wsg_gcl_request_kind(const char *text, size_t len);
void wsg_dispatch_line(gcl_conn_t *g, const char *line, size_t len, gcl_line_status_t line_status);
/* The connection's last plain query line (NAME?, as it came) again. */
void wsg_dispatch_repeated_query(gcl_conn_t *g);

/* send.c: every GCL line goes out here; sending changes no state but the
 * line count. The built line with its '\n' added (ERR REPLY 27 instead of a
 * cut one). */
void wsg_gcl_send(gcl_conn_t *g, wsg_textbuf_t *tb, wsg_msg_kind_t kind);
/* A whole line, its '\n' included, that surely fits a reply. Inline: the
 * replies to polled queries come this way. */
static inline void wsg_gcl_send_line(gcl_conn_t *g, const char *line, size_t len,
                                     wsg_msg_kind_t kind)
{
    g->lines_out++;
    wsg_conn_write(g->conn, line, len, kind);
}
void wsg_gcl_send_word(gcl_conn_t *g, const char *word, const char *name);
/* "ERR NAME code [text]"; command: its index in the dispatch table (what
 * the GCL observer is told), -1 for an unknown one. */
void wsg_gcl_send_error(gcl_conn_t *g, const char *name, int command, wsg_status_t status);

/* autosend.c */
void wsg_autosend_reschedule(gcl_conn_t *g);
void wsg_autosend_fire(wsg_timer_t *timer, uint64_t now_us);
bool wsg_autosend_any(const gcl_conn_t *g);
uint32_t wsg_gcl_flags(const gcl_conn_t *g, const wsg_snapshot_t *snap);

/* args.c: E_SUCCESS, E_INVALID_PARAMETER (wrong type) or E_RANGE_ERROR (a
 * bool that is neither 0 nor 1) */
wsg_status_t wsg_arg_float(const cmd_ctx_t *ctx, unsigned i, float *out);
wsg_status_t wsg_arg_int(const cmd_ctx_t *ctx, unsigned i, int32_t *out);
wsg_status_t wsg_arg_bool(const cmd_ctx_t *ctx, unsigned i, bool *out);
/* A quoted string, or (tolerated) a bare word. */
wsg_status_t wsg_arg_text(const cmd_ctx_t *ctx, unsigned i, const char **out);
/* Optional float argument i, or the fallback when it was not given. */
wsg_status_t wsg_arg_optional_float(const cmd_ctx_t *ctx, unsigned i, float fallback, float *out);
/* Reports input the manual does not allow but the device accepts. */
void wsg_note_tolerated(const cmd_ctx_t *ctx, const char *what);

/* Reply helpers */
void wsg_reply_ack(cmd_ctx_t *ctx);
void wsg_reply_float(cmd_ctx_t *ctx, float value);
void wsg_reply_int(cmd_ctx_t *ctx, int32_t value);
void wsg_reply_quoted(cmd_ctx_t *ctx, const char *value);
void wsg_reply_text(cmd_ctx_t *ctx, wsg_textbuf_t *tb);

/* Handlers */
wsg_status_t wsg_cmd_verbose(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_bye(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_home(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_move(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_grip(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_release(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_stop(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_faststop(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_fsack(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_pwt(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_clt(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_pos(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_speed(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_force(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_gripstate(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_gripstats(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_sysflags(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_temp(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_devtype(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_version(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_sn(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_tag(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_autosend(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_tare(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_fdata(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_ftype(cmd_ctx_t *ctx);
wsg_status_t wsg_cmd_fflags(cmd_ctx_t *ctx);

#endif
