/* SPDX-License-Identifier: BSD-3-Clause */
/* The GCL protocol driver (wsg_gcl.h): lines in, whole reply lines out, and
 * the formatting of every GCL message, final replies included. */
#include <stddef.h>
#include <string.h>

#include "gcl/gcl_internal.h"

static void gcl_open(wsg_conn_t *c)
{
    gcl_conn_t *g = gcl_of(c);
    const wsg_config_t *cfg = &conn_of(c)->dev->cfg;
    memset(g, 0, sizeof(*g));
    g->conn = conn_of(c);
    g->pwt_mm = cfg->default_pwt_mm;
    g->clt_mm = cfg->default_clt_mm;
    g->autosend_timer.fire = wsg_autosend_fire;
    wsg_gcl_linebuf_reset(&g->input);
}

/* A web page can make a browser POST to the device's port: the lines of
 * the body would run as commands. A stream that sends an HTTP line ends at
 * once, unanswered, as after BYE (no FAST STOP), and nothing after it runs
 * (the input loop stops at the goodbye). A datagram is no browser's. */
static bool refuse_http(gcl_conn_t *g, const gcl_linebuf_t *lb)
{
    if (g->conn->transport != WSG_TRANSPORT_STREAM || !wsg_gcl_line_is_http(lb->text)) {
        return false;
    }
    g->conn->said_goodbye = true;
    g->conn->refused_http = true;
    return true;
}

static void handle_completed_line(gcl_conn_t *g)
{
    const gcl_linebuf_t *lb = &g->input;
    g->lines_in++;
    wsg_conn_note_input(g->conn, lb->text, lb->len);
    if (!refuse_http(g, lb)) {
        wsg_dispatch_line(g, lb->text, lb->len, wsg_gcl_linebuf_status(lb));
    }
}

/* A poller repeats one query line: when the input starts with it again,
 * it needs neither a byte-by-byte assembly nor a parse. */
static size_t take_repeated_query(gcl_conn_t *g, const uint8_t *bytes, size_t len)
{
    if (g->query_line_len == 0 || wsg_conn_timed(g->conn)) {
        return 0; /* no query line yet, or every line waits for the processor */
    }
    size_t taken =
        wsg_gcl_linebuf_take_line(&g->input, bytes, len, g->query_line, g->query_line_len);
    if (taken != 0) {
        g->lines_in++;
        wsg_conn_note_input(g->conn, g->input.text, g->input.len);
        wsg_dispatch_repeated_query(g);
    }
    return taken;
}

/* A whole line under a timing profile: held for the command processor,
 * which runs it when its service time has passed (gcl_serve). */
static void hold_line(gcl_conn_t *g)
{
    wsg_proc_submit(g->conn, wsg_gcl_request_kind(g->input.text, g->input.len));
}

static size_t gcl_input(wsg_conn_t *c, const uint8_t *bytes, size_t len)
{
    gcl_conn_t *g = gcl_of(c);
    if (g->conn->request_waits) {
        return 0; /* the rest waits in the port, as in a busy device's receive buffer */
    }
    size_t i = 0;
    g->in_input = true;
    while (i < len && !g->conn->said_goodbye) {
        size_t taken = take_repeated_query(g, bytes + i, len - i);
        if (taken != 0) {
            i += taken;
            continue;
        }
        bool line_done = false;
        i += wsg_gcl_linebuf_feed_bytes(&g->input, bytes + i, len - i, &line_done);
        if (line_done) {
            if (wsg_conn_timed(g->conn)) {
                hold_line(g);
                break;
            }
            handle_completed_line(g);
        }
    }
    g->in_input = false;
    g->quiet_since_sense = false;           /* the port, the world and other connections run next */
    return g->conn->said_goodbye ? len : i; /* after a goodbye nothing more runs */
}

static void gcl_serve(wsg_conn_t *c)
{
    gcl_conn_t *g = gcl_of(c);
    g->quiet_since_sense = false;
    handle_completed_line(g);
}

static void gcl_end_datagram(wsg_conn_t *c)
{
    gcl_conn_t *g = gcl_of(c);
    if (!g->conn->said_goodbye && !g->conn->request_waits && wsg_gcl_linebuf_flush(&g->input)) {
        if (wsg_conn_timed(g->conn)) {
            hold_line(g);
            return;
        }
        handle_completed_line(g);
    }
}

static const char *const op_names[WSG_OP_COUNT] = {
    [WSG_OP_HOME] = "HOME",
    [WSG_OP_MOVE] = "MOVE",
    [WSG_OP_GRIP] = "GRIP",
    [WSG_OP_RELEASE] = "RELEASE",
};

/* The final reply of a long command: FIN NAME or ERR NAME code. */
static void gcl_done(wsg_conn_t *c, wsg_op_t op, wsg_status_t status)
{
    gcl_conn_t *g = gcl_of(c);
    const char *name = (unsigned)op < WSG_OP_COUNT ? op_names[op] : "?";
    g->cmd_failed = status != E_SUCCESS;
    if (status == E_SUCCESS) {
        wsg_gcl_send_word(g, "FIN", name);
    } else {
        wsg_gcl_send_error(g, name, wsg_gcl_command_index(name), status);
    }
}

static bool gcl_busy(const wsg_conn_t *c)
{
    return wsg_autosend_any(gcl_of_const(c));
}

/* The manual ends a connection with BYE(); the device copes without it. */
static void gcl_close(wsg_conn_t *c, wsg_close_reason_t why)
{
    gcl_conn_t *g = gcl_of(c);
    conn_t *conn = g->conn;
    bool missing =
        why == WSG_CLOSE_DROPPED && !conn->said_goodbye && conn->transport == WSG_TRANSPORT_STREAM;
    for (const wsg_gcl_observer_t *o = gcl_observers(g); missing && o != NULL; o = o->next) {
        if (o->tolerated != NULL) {
            o->tolerated(o->ctx, c, "BYE", "connection closed without BYE()");
        }
    }
    wsg_timer_cancel(&conn->dev->timers, &g->autosend_timer);
}

static bool gcl_partial(const wsg_conn_t *c)
{
    return wsg_gcl_linebuf_pending(&gcl_of_const(c)->input);
}

const wsg_proto_driver_t wsg_gcl_driver = {
    .name = "gcl",
    .open = gcl_open,
    .input = gcl_input,
    .end_datagram = gcl_end_datagram,
    .done = gcl_done,
    .busy = gcl_busy,
    .close = gcl_close,
    .partial = gcl_partial,
    .serve = gcl_serve,
};

void wsg_gcl_add_observer(wsg_device_t *dev, wsg_gcl_observer_t *node)
{
    wsg_gcl_observer_t **at = &dev_of(dev)->observers.gcl;
    while (*at != NULL && *at != node) {
        at = &(*at)->next;
    }
    if (*at == NULL) {
        node->next = NULL;
        *at = node;
    }
}

void wsg_gcl_remove_observer(wsg_device_t *dev, wsg_gcl_observer_t *node)
{
    wsg_gcl_observer_t **at = &dev_of(dev)->observers.gcl;
    while (*at != NULL && *at != node) {
        at = &(*at)->next;
    }
    if (*at != NULL) {
        *at = node->next;
        node->next = NULL;
    }
}

bool wsg_gcl_conn_info(const wsg_conn_t *c, wsg_gcl_conn_info_t *info)
{
    const conn_t *conn = conn_of_const(c);
    if (!conn->open || conn->drv != &wsg_gcl_driver) {
        return false;
    }
    const gcl_conn_t *g = gcl_of_const(c);
    info->verbose = g->verbose;
    info->pwt_mm = g->pwt_mm;
    info->clt_mm = g->clt_mm;
    info->cmd_failed = g->cmd_failed;
    info->lines_in = g->lines_in;
    info->lines_out = g->lines_out;
    for (unsigned v = 0; v < AS_COUNT; v++) {
        const gcl_autosend_sub_t *sub = &g->autosend[v];
        info->autosend[v] =
            (wsg_gcl_autosend_info_t){sub->interval_ms, sub->next_due_us, sub->use_delta,
                                      sub->delta,       sub->on_change,   sub->missed};
    }
    return true;
}
