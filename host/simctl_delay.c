#include "simctl_delay.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "gripper.h"
#include "hal_clock.h"
#include "log.h"

/* What one delayed session may hold: past it the delay ends early and every
 * held line is delivered (a reply is never dropped). 256 KiB is about half a
 * minute of the fastest AUTOSEND streams. */
#define HELD_MAX_BYTES (256u * 1024u)
#define HELD_FIRST_BYTES 4096u
#define RECORD_HEADER 3u /* kind, length high byte, length low byte */

typedef struct {
    bool armed;
    bool holding;
    uint64_t generation;
    uint32_t delay_us;
    uint64_t release_us;
    const wsg_session_io_t *io; /* the port's own I/O, restored on release */
    void *io_ctx;
    unsigned lines;
    size_t used;
    size_t cap;
    uint8_t *held; /* malloc'd, grows up to HELD_MAX_BYTES */
} delay_slot_t;

static delay_slot_t slots[WSG_MAX_SESSIONS];

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

static bool hold_line(delay_slot_t *d, const char *line, size_t len, wsg_line_kind_t kind)
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

static void release(unsigned index, bool send);

/* The hold is full: the delay ends now, everything held goes out in order,
 * then this line. Logged once per DELAY, since the delay is over. */
static void overflow(delay_slot_t *d, const char *line, size_t len, wsg_line_kind_t kind)
{
    host_logf(HAL_LOG_WARN,
              "DELAY of session %llu ended early: more than %u KiB of lines held; "
              "delivering them now",
              (unsigned long long)d->generation, HELD_MAX_BYTES / 1024u);
    const wsg_session_io_t *io = d->io;
    void *io_ctx = d->io_ctx;
    release((unsigned)(d - slots), true);
    io->write_line(io_ctx, line, len, kind);
}

static void delayed_write(void *ctx, const char *line, size_t len, wsg_line_kind_t kind)
{
    delay_slot_t *d = ctx;
    if (!d->holding && kind == WSG_LINE_REPLY) {
        d->holding = true;
        d->release_us = hal_clock_now_us() + d->delay_us;
    }
    if (!d->holding) {
        d->io->write_line(d->io_ctx, line, len, kind); /* AUTOSEND before the reply */
    } else if (!hold_line(d, line, len, kind)) {
        overflow(d, line, len, kind);
    }
}

static const wsg_session_io_t delayed_io = {.write_line = delayed_write};

void simctl_delay_arm(wsg_session_t *s, uint32_t delay_us)
{
    delay_slot_t *d = &slots[s->index];
    if (d->armed && d->generation == s->generation && s->io == &delayed_io) {
        d->delay_us = delay_us; /* re-armed before it took effect */
        return;
    }
    drop_held(d);
    memset(d, 0, sizeof(*d));
    d->armed = true;
    d->generation = s->generation;
    d->delay_us = delay_us;
    d->io = s->io;
    d->io_ctx = s->io_ctx;
    s->io = &delayed_io;
    s->io_ctx = d;
}

/* The session the slot stands in for, if it still exists. */
static wsg_session_t *owner(unsigned index, const delay_slot_t *d)
{
    wsg_session_t *s = &gripper_device()->sessions[index];
    bool same = s->in_use && s->generation == d->generation && s->io == &delayed_io;
    return same ? s : NULL;
}

static void deliver(const delay_slot_t *d)
{
    size_t at = 0;
    while (at < d->used) {
        const uint8_t *p = &d->held[at];
        size_t len = ((size_t)p[1] << 8) | p[2];
        d->io->write_line(d->io_ctx, (const char *)(p + RECORD_HEADER), len, (wsg_line_kind_t)p[0]);
        at += RECORD_HEADER + len;
    }
}

/* Gives the session its own I/O back and hands over what was held. */
static void release(unsigned index, bool send)
{
    delay_slot_t *d = &slots[index];
    wsg_session_t *s = owner(index, d);
    d->armed = false;
    d->holding = false;
    if (s != NULL) { /* else the session went away: its lines have no receiver */
        s->io = d->io;
        s->io_ctx = d->io_ctx;
        if (send) {
            deliver(d);
        }
    }
    drop_held(d);
}

unsigned simctl_delay_release_due(uint64_t now_us)
{
    unsigned released = 0;
    for (unsigned i = 0; i < WSG_MAX_SESSIONS; i++) {
        delay_slot_t *d = &slots[i];
        if (d->armed && owner(i, d) == NULL) {
            release(i, false); /* closed while armed */
        } else if (d->armed && d->holding && now_us >= d->release_us) {
            release(i, true);
            released++;
        }
    }
    return released;
}

uint64_t simctl_delay_next_us(void)
{
    uint64_t next = UINT64_MAX;
    for (unsigned i = 0; i < WSG_MAX_SESSIONS; i++) {
        if (slots[i].armed && slots[i].holding && slots[i].release_us < next) {
            next = slots[i].release_us;
        }
    }
    return next;
}

void simctl_delay_clear_all(bool send)
{
    for (unsigned i = 0; i < WSG_MAX_SESSIONS; i++) {
        if (slots[i].armed) {
            release(i, send);
        }
    }
}

bool simctl_delay_info(unsigned i, simctl_delay_info_t *out)
{
    unsigned seen = 0;
    for (unsigned k = 0; k < WSG_MAX_SESSIONS; k++) {
        const delay_slot_t *d = &slots[k];
        if (!d->armed || owner(k, d) == NULL) {
            continue;
        }
        if (seen++ == i) {
            *out = (simctl_delay_info_t){d->generation, d->delay_us, d->holding, d->release_us,
                                         d->lines};
            return true;
        }
    }
    return false;
}
