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
#define DELAYS_MAX 144u  /* as many as connections the host serves */

typedef struct {
    bool armed;
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
} delay_slot_t;

static delay_slot_t slots[DELAYS_MAX];
static unsigned armed_count; /* nothing to scan while it is 0 */

/* Room for need more bytes; false past HELD_MAX_BYTES (or out of memory). */
static bool make_room(delay_slot_t *d, size_t need)
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

static void drop_held(delay_slot_t *d)
{
    free(d->held);
    d->held = NULL;
    d->used = 0;
    d->cap = 0;
    d->lines = 0;
}

static bool hold_line(delay_slot_t *d, const char *line, size_t len, wsg_msg_kind_t kind)
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

static void release(delay_slot_t *d, bool send);

/* The hold is full: the delay ends now, everything held goes out in order,
 * then this line. Logged once per DELAY, since the delay is over. */
static void overflow(delay_slot_t *d, const char *line, size_t len, wsg_msg_kind_t kind)
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
    delay_slot_t *d = ctx;
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

static const wsg_conn_io_t delayed_io = {.write = delayed_write};

/* The slot that stands in for the connection's I/O, if it is delayed. */
static delay_slot_t *slot_of(const wsg_conn_t *c)
{
    const wsg_conn_io_t *io = NULL;
    void *io_ctx = NULL;
    wsg_conn_get_io(c, &io, &io_ctx);
    return io == &delayed_io ? io_ctx : NULL;
}

static delay_slot_t *free_slot(void)
{
    for (unsigned i = 0; i < DELAYS_MAX; i++) {
        if (!slots[i].armed) {
            return &slots[i];
        }
    }
    return NULL;
}

void simctl_delay_arm(wsg_conn_t *c, uint32_t delay_us)
{
    delay_slot_t *d = slot_of(c);
    if (d != NULL) {
        d->delay_us = delay_us; /* re-armed before it took effect */
        return;
    }
    const wsg_conn_io_t *io = NULL;
    void *io_ctx = NULL;
    wsg_conn_get_io(c, &io, &io_ctx);
    d = free_slot();
    if (d == NULL) {
        host_logf(HAL_LOG_WARN, "DELAY: every delay slot is taken");
        return;
    }
    drop_held(d);
    memset(d, 0, sizeof(*d));
    d->armed = true;
    d->device = wsg_conn_device(c);
    d->conn_id = wsg_conn_id(c);
    d->delay_us = delay_us;
    d->io = io;
    d->io_ctx = io_ctx;
    armed_count++;
    wsg_conn_set_io(c, &delayed_io, d);
}

/* The connection the slot stands in for, if it is still open. */
static wsg_conn_t *owner(const delay_slot_t *d)
{
    wsg_conn_t *c = wsg_device_conn_by_id((wsg_device_t *)d->device, d->conn_id);
    if (c == NULL) {
        return NULL;
    }
    const wsg_conn_io_t *io = NULL;
    void *io_ctx = NULL;
    wsg_conn_get_io(c, &io, &io_ctx);
    return io == &delayed_io && io_ctx == d ? c : NULL;
}

static void deliver(const delay_slot_t *d)
{
    size_t at = 0;
    while (at < d->used) {
        const uint8_t *p = &d->held[at];
        size_t len = ((size_t)p[1] << 8) | p[2];
        d->io->write(d->io_ctx, (const char *)(p + RECORD_HEADER), len, (wsg_msg_kind_t)p[0]);
        at += RECORD_HEADER + len;
    }
}

/* Gives the connection its own I/O back and hands over what was held. */
static void release(delay_slot_t *d, bool send)
{
    wsg_conn_t *c = owner(d);
    d->armed = false;
    d->holding = false;
    armed_count--;
    if (c != NULL) { /* else the connection went away: its lines have no receiver */
        wsg_conn_set_io(c, d->io, d->io_ctx);
        if (send) {
            deliver(d);
        }
    }
    drop_held(d);
}

unsigned simctl_delay_release_due(uint64_t now_us)
{
    if (armed_count == 0) {
        return 0; /* the common case, at every deadline */
    }
    unsigned released = 0;
    for (unsigned i = 0; i < DELAYS_MAX && armed_count > 0; i++) {
        delay_slot_t *d = &slots[i];
        if (d->armed && owner(d) == NULL) {
            release(d, false); /* closed while armed */
        } else if (d->armed && d->holding && now_us >= d->release_us) {
            release(d, true);
            released++;
        }
    }
    return released;
}

uint64_t simctl_delay_next_us(void)
{
    uint64_t next = UINT64_MAX;
    for (unsigned i = 0; i < DELAYS_MAX && armed_count > 0; i++) {
        if (slots[i].armed && slots[i].holding && slots[i].release_us < next) {
            next = slots[i].release_us;
        }
    }
    return next;
}

void simctl_delay_clear_all(const wsg_device_t *device, bool send)
{
    for (unsigned i = 0; i < DELAYS_MAX && armed_count > 0; i++) {
        if (slots[i].armed && slots[i].device == device) {
            release(&slots[i], send);
        }
    }
}

bool simctl_delay_holding(const wsg_conn_t *c)
{
    const delay_slot_t *d = slot_of(c);
    return d != NULL && d->holding;
}

bool simctl_delay_info(unsigned i, simctl_delay_info_t *out)
{
    unsigned seen = 0;
    for (unsigned k = 0; k < DELAYS_MAX && armed_count > 0; k++) {
        const delay_slot_t *d = &slots[k];
        if (!d->armed || owner(d) == NULL) {
            continue;
        }
        if (seen++ == i) {
            *out = (simctl_delay_info_t){d->device,  d->conn_id,    d->delay_us,
                                         d->holding, d->release_us, d->lines};
            return true;
        }
    }
    return false;
}
