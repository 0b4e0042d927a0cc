/* SPDX-License-Identifier: BSD-3-Clause */
#include "delay.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"
#include "log.h"

/* What one delayed connection may hold: past it the delay ends early and
 * every held line is delivered (a reply is never dropped). 256 KiB is about
 * half a minute of the fastest AUTOSEND streams. */
#define HELD_MAX_BYTES (256u * 1024u)
#define HELD_FIRST_BYTES 4096u
#define RECORD_HEADER 3u /* kind, length high byte, length low byte */
#define DELAYS_MAX 144u  /* armed at once, as many as connections the host serves */

struct simctl_delay {
    list_node_t link; /* on the instance's list of armed delays */
    bool holding;
    const wsg_device_t *device; /* whose connection (ids are per device) */
    uint64_t conn_id;
    uint32_t delay_us;
    uint64_t release_us;
    const wsg_conn_io_t *io; /* the port's own I/O, restored on release */
    void *io_ctx;
    unsigned lines;
    size_t used;
    size_t cap;
    uint8_t *held; /* malloc'd, grows up to HELD_MAX_BYTES */
    simctl_delays_t *delays;
};

typedef struct simctl_delay delay_t;

#define DELAY(node) LIST_ITEM(node, delay_t, link)

/* Room for need more bytes; false past HELD_MAX_BYTES (or out of memory). */
static bool make_room(delay_t *d, size_t need)
{
    if (d->used + need <= d->cap) {
        return true;
    }
    if (d->used + need > HELD_MAX_BYTES) {
        return false;
    }
    size_t cap = d->cap == 0 ? HELD_FIRST_BYTES : d->cap;
    while (cap < d->used + need) {
        cap *= 2;
    }
    cap = cap < HELD_MAX_BYTES ? cap : HELD_MAX_BYTES;
    uint8_t *grown = realloc(d->held, cap);
    if (grown == NULL) {
        return false;
    }
    d->held = grown;
    d->cap = cap;
    return true;
}

static void drop_held(delay_t *d)
{
    free(d->held);
    d->held = NULL;
    d->used = 0;
    d->cap = 0;
    d->lines = 0;
}

static bool hold_line(delay_t *d, const char *line, size_t len, wsg_msg_kind_t kind)
{
    if (len > 0xffffu || !make_room(d, RECORD_HEADER + len)) {
        return false;
    }
    uint8_t *p = &d->held[d->used];
    p[0] = (uint8_t)kind;
    p[1] = (uint8_t)(len >> 8);
    p[2] = (uint8_t)len;
    memcpy(p + RECORD_HEADER, line, len);
    d->used += RECORD_HEADER + len;
    d->lines++;
    return true;
}

static void release(delay_t *d, bool send);

/* The hold is full: the delay ends now, everything held goes out in order,
 * then this line. Logged once per DELAY, since the delay is over. */
static void overflow(delay_t *d, const char *line, size_t len, wsg_msg_kind_t kind)
{
    host_logf(HAL_LOG_WARN,
              "DELAY of session %llu ended early: more than %u KiB of lines held; "
              "delivering them now",
              (unsigned long long)d->conn_id, HELD_MAX_BYTES / 1024u);
    const wsg_conn_io_t *io = d->io;
    void *io_ctx = d->io_ctx;
    release(d, true);
    io->write(io_ctx, line, len, kind);
}

static void delayed_write(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    delay_t *d = ctx;
    if (!d->holding && kind == WSG_MSG_REPLY) {
        d->holding = true;
        d->release_us = hal_clock_now_us() + d->delay_us;
    }
    if (!d->holding) {
        d->io->write(d->io_ctx, line, len, kind); /* AUTOSEND before the reply */
    } else if (!hold_line(d, line, len, kind)) {
        overflow(d, line, len, kind);
    }
}

/* Held replies still count as queued: a half-closed connection waits for
 * them too (the port asks through wsg_conn_replies_held()). */
static bool delayed_held(void *ctx)
{
    const delay_t *d = ctx;
    return d->holding;
}

/* The port's resume (a timing profile) passes through the delay. */
static void delayed_resume(void *ctx)
{
    const delay_t *d = ctx;
    if (d->io->resume != NULL) {
        d->io->resume(d->io_ctx);
    }
}

static const wsg_conn_io_t delayed_io = {
    .write = delayed_write, .held = delayed_held, .resume = delayed_resume};

/* The delay that stands in for the connection's I/O, if it is delayed. */
static delay_t *delay_of(const wsg_conn_t *c)
{
    const wsg_conn_io_t *io = NULL;
    void *io_ctx = NULL;
    wsg_conn_get_io(c, &io, &io_ctx);
    return io == &delayed_io ? io_ctx : NULL;
}

static void link_delay(simctl_delays_t *ds, delay_t *d)
{
    list_push_back(&ds->armed, &d->link);
    ds->count++;
}

static void unlink_delay(simctl_delays_t *ds, delay_t *d)
{
    list_remove(&ds->armed, &d->link);
    ds->count--;
}

void simctl_delay_arm(simctl_delays_t *ds, wsg_conn_t *c, uint32_t delay_us)
{
    delay_t *d = delay_of(c);
    if (d != NULL) {
        d->delay_us = delay_us; /* re-armed before it took effect */
        return;
    }
    d = ds->count < DELAYS_MAX ? calloc(1, sizeof(*d)) : NULL;
    if (d == NULL) {
        host_logf(HAL_LOG_WARN, "DELAY: every delay slot is taken");
        return;
    }
    wsg_conn_get_io(c, &d->io, &d->io_ctx);
    d->delays = ds;
    d->device = wsg_conn_device(c);
    d->conn_id = wsg_conn_id(c);
    d->delay_us = delay_us;
    link_delay(ds, d);
    wsg_conn_set_io(c, &delayed_io, d);
}

/* The connection the delay stands in for, if it is still open. */
static wsg_conn_t *owner(const delay_t *d)
{
    wsg_conn_t *c = wsg_device_conn_by_id((wsg_device_t *)d->device, d->conn_id);
    return c != NULL && delay_of(c) == d ? c : NULL;
}

static void deliver(const delay_t *d)
{
    size_t at = 0;
    while (at < d->used) {
        const uint8_t *p = &d->held[at];
        size_t len = ((size_t)p[1] << 8) | p[2];
        d->io->write(d->io_ctx, (const char *)(p + RECORD_HEADER), len, (wsg_msg_kind_t)p[0]);
        at += RECORD_HEADER + len;
    }
}

/* Gives the connection its own I/O back, hands over what was held and
 * frees the delay. */
static void release(delay_t *d, bool send)
{
    wsg_conn_t *c = owner(d);
    unlink_delay(d->delays, d);
    if (c != NULL) { /* else the connection went away: its lines have no receiver */
        wsg_conn_set_io(c, d->io, d->io_ctx);
        if (send) {
            deliver(d);
        }
    }
    drop_held(d);
    free(d);
}

unsigned simctl_delay_release_due(simctl_delays_t *ds, uint64_t now_us)
{
    unsigned released = 0;
    LIST_EACH_SAFE (node, &ds->armed) {
        delay_t *d = DELAY(node);
        if (owner(d) == NULL) {
            release(d, false); /* closed while armed */
        } else if (d->holding && now_us >= d->release_us) {
            release(d, true);
            released++;
        }
    }
    return released;
}

uint64_t simctl_delay_next_us(const simctl_delays_t *ds)
{
    uint64_t next = UINT64_MAX;
    LIST_EACH (node, &ds->armed) {
        const delay_t *d = DELAY(node);
        if (d->holding && d->release_us < next) {
            next = d->release_us;
        }
    }
    return next;
}

unsigned simctl_delay_clear_all(simctl_delays_t *ds, const wsg_device_t *device, bool send)
{
    unsigned cleared = 0;
    LIST_EACH_SAFE (node, &ds->armed) {
        delay_t *d = DELAY(node);
        if (d->device == device) {
            cleared += owner(d) != NULL ? 1u : 0u;
            release(d, send);
        }
    }
    return cleared;
}

bool simctl_delay_info(const wsg_conn_t *c, simctl_delay_info_t *out)
{
    const delay_t *d = delay_of(c);
    if (d == NULL) {
        return false;
    }
    *out = (simctl_delay_info_t){d->device,  d->conn_id,    d->delay_us,
                                 d->holding, d->release_us, d->lines};
    return true;
}
