/* SPDX-License-Identifier: BSD-3-Clause */
/* A connection's private state and what protocol drivers use of it. */
#ifndef WSG_CONN_PRIV_H
#define WSG_CONN_PRIV_H

#include "priv/wsg_dev.h"

#define CONN_PROTO_BYTES (WSG_CONN_STORAGE_BYTES - 160)

typedef struct wsg_conn_impl {
    wsg_dev_t *dev;
    const wsg_proto_driver_t *drv; /* NULL until the first byte chose one */
    const wsg_conn_io_t *io;
    void *io_ctx;
    uint64_t id;
    wsg_transport_t transport;
    wsg_owner_t owner; /* what the device's completion events reach */
    bool open;
    bool said_goodbye;    /* the protocol's goodbye was answered: close after flushing */
    bool close_announced; /* the protocol announced its close: dropping it is no fault */
    bool refused_http;    /* closed unanswered: it sent an HTTP line (wsg_gcl_line_is_http) */
    uint32_t messages_in; /* whole messages taken in (wsg_conn_count_input) */
    /* the command processor (a timing profile, firmware/conn/proc.c) */
    bool request_waits;                /* the driver holds a whole request for it */
    bool next_held;                    /* bytes after that request stayed with the port */
    bool stream_slot;                  /* its stream frames' slot is reserved (pace.c) */
    wsg_timer_t serve_timer;           /* due when the processor has served the request */
    uint32_t waited_own;               /* requests that waited behind this connection's own */
    uint32_t waited_others;            /* requests that waited behind other connections' work */
    struct wsg_conn_impl *next, *prev; /* the device's open connections */
    WSG_ALIGNED unsigned char proto[CONN_PROTO_BYTES]; /* the driver's state */
} conn_t;

_Static_assert(sizeof(conn_t) <= sizeof(wsg_conn_t),
               "WSG_CONN_STORAGE_BYTES (wsg_opts.h) is too small for a connection");

static inline conn_t *conn_of(wsg_conn_t *c)
{
    return (conn_t *)(void *)c;
}

static inline const conn_t *conn_of_const(const wsg_conn_t *c)
{
    return (const conn_t *)(const void *)c;
}

static inline wsg_conn_t *conn_public(conn_t *c)
{
    return (wsg_conn_t *)(void *)c;
}

/* wsg_conn_input() of a connection that has no driver yet: its first byte
 * chooses one. Apart, so that the input of every other stays short. */
size_t wsg_conn_input_choosing_driver(wsg_conn_t *conn, const uint8_t *bytes, size_t len);

/* What a driver's input took of len bytes: fewer only while a request
 * waits for the processor, and then the rest is a next request held back
 * behind it (counted when it is submitted). */
static inline size_t wsg_conn_took(conn_t *c, size_t taken, size_t len)
{
    if (taken < len) {
        c->next_held = true;
    }
    return taken;
}

/* The command processor (proc.c): the driver holds a whole request and
 * takes no more bytes; the processor serves it at the end of its slot
 * through the driver's serve(). */
void wsg_proc_submit(conn_t *c, wsg_request_kind_t kind);
void wsg_proc_conn_open(conn_t *c);
void wsg_proc_conn_close(conn_t *c);

/* Whether the device runs a timing profile: the one branch the request
 * path takes under "ideal". */
static inline bool wsg_conn_timed(const conn_t *c)
{
    return c->dev->cfg.timing.enabled;
}

/* The observers' view of a message in or out (wsg_conn_observer_t). */
void wsg_conn_show_input(conn_t *c, const char *bytes, size_t len);
void wsg_conn_show_output(conn_t *c, const char *bytes, size_t len);
/* A read arrived (before its messages); the connection closes. */
void wsg_conn_show_read(conn_t *c, const uint8_t *bytes, size_t len);
void wsg_conn_show_close(conn_t *c, wsg_close_reason_t why, bool fast_stop);

/* One whole message out: observers, then the port's write. Inline: every
 * reply goes through here, and mostly nobody observes. */
static inline void wsg_conn_write(conn_t *c, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    if (!c->open || c->io == NULL) {
        return;
    }
    if (c->dev->observers.conn != NULL) {
        wsg_conn_show_output(c, bytes, len);
    }
    c->io->write(c->io_ctx, bytes, len, kind);
}

/* A message in, counted only (a driver that builds the observers' copy
 * only when someone observes). */
static inline void wsg_conn_count_input(conn_t *c)
{
    c->messages_in++;
}

/* A message in, as the driver framed it: counted, then shown to observers. */
static inline void wsg_conn_note_input(conn_t *c, const char *bytes, size_t len)
{
    wsg_conn_count_input(c);
    if (c->dev->observers.conn != NULL) {
        wsg_conn_show_input(c, bytes, len);
    }
}

#endif
