/* SPDX-License-Identifier: BSD-3-Clause */
/* Protocol-neutral connections (wsg_conn.h): the device's list of open
 * connections, the protocol driver hook and the close rule. */
#include <stddef.h>
#include <string.h>

#include "priv/conn.h"

/* Appended: the list is in opening order. */
static void link_conn(wsg_dev_t *dev, conn_t *c)
{
    c->next = NULL;
    c->prev = dev->conns_tail;
    if (dev->conns_tail != NULL) {
        dev->conns_tail->next = c;
    } else {
        dev->conns = c;
    }
    dev->conns_tail = c;
}

static void unlink_conn(wsg_dev_t *dev, conn_t *c)
{
    if (c->prev != NULL) {
        c->prev->next = c->next;
    } else {
        dev->conns = c->next;
    }
    if (c->next != NULL) {
        c->next->prev = c->prev;
    } else {
        dev->conns_tail = c->prev;
    }
    c->next = NULL;
    c->prev = NULL;
}

static void owner_done(wsg_owner_t *owner, wsg_op_t op, wsg_status_t status)
{
    conn_t *c = (conn_t *)(void *)((char *)owner - offsetof(conn_t, owner));
    if (c->open && c->drv != NULL) {
        c->drv->done(conn_public(c), op, status);
    }
}

void wsg_conn_open(wsg_conn_t *conn, wsg_device_t *device, const wsg_proto_driver_t *drv,
                   wsg_transport_t transport, const wsg_conn_io_t *io, void *io_ctx)
{
    conn_t *c = conn_of(conn);
    memset(c, 0, sizeof(*c));
    c->dev = dev_of(device);
    c->io = io;
    c->io_ctx = io_ctx;
    c->transport = transport;
    c->id = wsg_device_next_conn_id(device);
    c->owner.done = owner_done;
    c->open = true;
    wsg_proc_conn_open(c);
    link_conn(c->dev, c);
    c->drv = drv;
    if (drv != NULL) {
        drv->open(conn);
    }
}

void wsg_conn_set_drivers(wsg_device_t *device, const wsg_proto_driver_t *const *drivers,
                          size_t count)
{
    wsg_dev_t *dev = dev_of(device);
    dev->drivers = drivers;
    dev->driver_count = count;
}

/* Protocol auto-detection: the first byte of a connection opened without a
 * driver chooses one from the port's table, the first that claims it (a
 * driver without detect() claims any byte). NULL: the table has none. */
static const wsg_proto_driver_t *detect(const wsg_dev_t *dev, uint8_t first_byte)
{
    for (size_t i = 0; i < dev->driver_count; i++) {
        const wsg_proto_driver_t *drv = dev->drivers[i];
        if (drv->detect == NULL || drv->detect(first_byte)) {
            return drv;
        }
    }
    return NULL;
}

size_t wsg_conn_input_choosing_driver(wsg_conn_t *conn, const uint8_t *bytes, size_t len)
{
    conn_t *c = conn_of(conn);
    if (!c->open || len == 0) {
        return len;
    }
    c->drv = detect(c->dev, bytes[0]);
    if (c->drv == NULL) {
        return len; /* no driver speaks it: nothing can answer */
    }
    c->drv->open(conn);
    return wsg_conn_took(c, c->drv->input(conn, bytes, len), len);
}

size_t wsg_conn_input(wsg_conn_t *conn, const uint8_t *bytes, size_t len)
{
    conn_t *c = conn_of(conn);
    if (c->dev->observers.conn_readers != 0) {
        wsg_conn_show_read(c, bytes, len); /* apart: a read pays one test */
    }
    return wsg_conn_input_kept(conn, bytes, len);
}

size_t wsg_conn_input_kept(wsg_conn_t *conn, const uint8_t *bytes, size_t len)
{
    conn_t *c = conn_of(conn);
    const wsg_proto_driver_t *drv = c->drv;
    if (drv == NULL) {
        return wsg_conn_input_choosing_driver(conn, bytes, len);
    }
    if (!c->open || len == 0) {
        return len;
    }
    return wsg_conn_took(c, drv->input(conn, bytes, len), len);
}

void wsg_conn_end_datagram(wsg_conn_t *conn)
{
    conn_t *c = conn_of(conn);
    if (c->open && c->drv != NULL) {
        c->drv->end_datagram(conn);
    }
}

bool wsg_conn_wants_close(const wsg_conn_t *conn)
{
    return conn_of_const(conn)->said_goodbye;
}

bool wsg_conn_refused_http(const wsg_conn_t *conn)
{
    return conn_of_const(conn)->refused_http;
}

bool wsg_conn_close_announced(const wsg_conn_t *conn)
{
    const conn_t *c = conn_of_const(conn);
    return c->said_goodbye || c->close_announced;
}

void wsg_conn_close(wsg_conn_t *conn, wsg_close_reason_t why)
{
    conn_t *c = conn_of(conn);
    if (!c->open) {
        return;
    }
    bool raise_fast_stop = why == WSG_CLOSE_DROPPED && !c->said_goodbye && !c->close_announced &&
                           c->transport == WSG_TRANSPORT_STREAM &&
                           c->dev->cfg.disconnect_raises_faststop;
    wsg_conn_show_close(c, why, raise_fast_stop);
    wsg_device_detach(dev_public(c->dev), &c->owner);
    wsg_proc_conn_close(c);
    if (c->drv != NULL) {
        c->drv->close(conn, why); /* ends its timers */
    }
    unlink_conn(c->dev, c);
    c->open = false;
    c->io = NULL;
    if (raise_fast_stop) {
        wsg_motion_fast_stop(c->dev, "connection closed without BYE");
    }
}

bool wsg_conn_is_open(const wsg_conn_t *conn)
{
    return conn_of_const(conn)->open;
}

uint64_t wsg_conn_id(const wsg_conn_t *conn)
{
    return conn_of_const(conn)->id;
}

wsg_transport_t wsg_conn_transport(const wsg_conn_t *conn)
{
    return conn_of_const(conn)->transport;
}

wsg_device_t *wsg_conn_device(const wsg_conn_t *conn)
{
    return dev_public(conn_of_const(conn)->dev);
}

wsg_owner_t *wsg_conn_owner(wsg_conn_t *conn)
{
    return &conn_of(conn)->owner;
}

bool wsg_conn_owns_motion(const wsg_conn_t *conn)
{
    const conn_t *c = conn_of_const(conn);
    return c->open && wsg_device_owns_motion(dev_public(c->dev), &c->owner);
}

bool wsg_conn_busy(const wsg_conn_t *conn)
{
    const conn_t *c = conn_of_const(conn);
    if (!c->open) {
        return false;
    }
    return wsg_conn_owns_motion(conn) || (c->drv != NULL && c->drv->busy(conn));
}

void wsg_conn_get_io(const wsg_conn_t *conn, const wsg_conn_io_t **io, void **io_ctx)
{
    const conn_t *c = conn_of_const(conn);
    *io = c->io;
    *io_ctx = c->io_ctx;
}

void wsg_conn_set_io(wsg_conn_t *conn, const wsg_conn_io_t *io, void *io_ctx)
{
    conn_t *c = conn_of(conn);
    c->io = io;
    c->io_ctx = io_ctx;
}

bool wsg_conn_replies_held(const wsg_conn_t *conn)
{
    const conn_t *c = conn_of_const(conn);
    return c->io != NULL && c->io->held != NULL && c->io->held(c->io_ctx);
}

void wsg_conn_add_observer(wsg_device_t *device, wsg_conn_observer_t *node)
{
    wsg_conn_observer_t **at = &dev_of(device)->observers.conn;
    while (*at != NULL && *at != node) {
        at = &(*at)->next;
    }
    if (*at == NULL) {
        node->next = NULL;
        *at = node;
        dev_of(device)->observers.conn_readers += node->read != NULL ? 1u : 0u;
    }
}

void wsg_conn_remove_observer(wsg_device_t *device, wsg_conn_observer_t *node)
{
    wsg_conn_observer_t **at = &dev_of(device)->observers.conn;
    while (*at != NULL && *at != node) {
        at = &(*at)->next;
    }
    if (*at != NULL) {
        *at = node->next;
        node->next = NULL;
        dev_of(device)->observers.conn_readers -= node->read != NULL ? 1u : 0u;
    }
}

uint32_t wsg_conn_messages_in(const wsg_conn_t *conn)
{
    return conn_of_const(conn)->messages_in;
}

bool wsg_conn_partial_input(const wsg_conn_t *conn)
{
    const conn_t *c = conn_of_const(conn);
    return c->open && c->drv != NULL && c->drv->partial != NULL && c->drv->partial(conn);
}

void wsg_conn_show_input(conn_t *c, const char *bytes, size_t len)
{
    for (const wsg_conn_observer_t *o = c->dev->observers.conn; o != NULL; o = o->next) {
        if (o->message_in != NULL) {
            o->message_in(o->ctx, conn_public(c), bytes, len);
        }
    }
}

void wsg_conn_show_read(conn_t *c, const uint8_t *bytes, size_t len)
{
    if (!c->open || len == 0) {
        return; /* nothing arrives at a closed connection */
    }
    for (const wsg_conn_observer_t *o = c->dev->observers.conn; o != NULL; o = o->next) {
        if (o->read != NULL) {
            o->read(o->ctx, conn_public(c), bytes, len);
        }
    }
}

void wsg_conn_show_close(conn_t *c, wsg_close_reason_t why, bool fast_stop)
{
    for (const wsg_conn_observer_t *o = c->dev->observers.conn; o != NULL; o = o->next) {
        if (o->closed != NULL) {
            o->closed(o->ctx, conn_public(c), why, fast_stop);
        }
    }
}

void wsg_conn_show_output(conn_t *c, const char *bytes, size_t len)
{
    for (const wsg_conn_observer_t *o = c->dev->observers.conn; o != NULL; o = o->next) {
        if (o->message_out != NULL) {
            o->message_out(o->ctx, conn_public(c), bytes, len);
        }
    }
}

wsg_conn_t *wsg_device_conn_first(wsg_device_t *device)
{
    conn_t *c = dev_of(device)->conns;
    return c != NULL ? conn_public(c) : NULL;
}

wsg_conn_t *wsg_conn_next(const wsg_conn_t *conn)
{
    conn_t *c = conn_of_const(conn)->next;
    return c != NULL ? conn_public(c) : NULL;
}

wsg_conn_t *wsg_device_conn_by_id(wsg_device_t *device, uint64_t id)
{
    for (conn_t *c = dev_of(device)->conns; c != NULL; c = c->next) {
        if (c->id == id) {
            return conn_public(c);
        }
    }
    return NULL;
}
