/* SPDX-License-Identifier: BSD-3-Clause */
/* Feed and step (wsg_runner.h). */
#include "hal_clock.h"
#include "wsg/wsg_runner.h"

static uint64_t advance(wsg_runner_t *r)
{
    uint64_t now = hal_clock_now_us();
    if (r->advance != NULL) {
        r->advance(r->advance_ctx, now);
    }
    return now;
}

/* What input at `now` started is due from the next instant on, never at
 * this one: on a paused clock it runs at the next step of time. */
static void due_after(wsg_runner_t *r, uint64_t now)
{
    uint64_t due = wsg_device_next_deadline_us(r->dev);
    due = due > now + 1u ? due : now + 1u;
    r->next_deadline_us = due < r->next_deadline_us ? due : r->next_deadline_us;
}

void wsg_runner_init(wsg_runner_t *r, wsg_device_t *dev, void (*advance_hook)(void *, uint64_t),
                     void *advance_ctx)
{
    r->dev = dev;
    r->advance = advance_hook;
    r->advance_ctx = advance_ctx;
    wsg_runner_due_now(r);
}

void wsg_runner_due_now(wsg_runner_t *r)
{
    r->next_deadline_us = hal_clock_now_us();
}

/* Input into the device at the present instant; returns that instant. */
static uint64_t feed_input(wsg_runner_t *r, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                           bool end_of_datagram)
{
    uint64_t now = advance(r);
    r->taken = wsg_conn_input(c, bytes, len);
    if (end_of_datagram && r->taken == len) { /* a datagram held back ends later */
        wsg_conn_end_datagram(c);
    }
    return now;
}

bool wsg_runner_feed_before_poll(wsg_runner_t *r, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                                 bool end_of_datagram)
{
    uint64_t now = feed_input(r, c, bytes, len, end_of_datagram);
    /* what wsg_runner_poll() would do now: step, or store another deadline */
    return now >= r->next_deadline_us || wsg_device_next_deadline_us(r->dev) != r->next_deadline_us;
}

void wsg_runner_feed(wsg_runner_t *r, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                     bool end_of_datagram)
{
    (void)feed_input(r, c, bytes, len, end_of_datagram);
    due_after(r, hal_clock_now_us()); /* input takes no device time */
}

void wsg_runner_input_done(wsg_runner_t *r)
{
    due_after(r, advance(r));
}

uint64_t wsg_runner_poll(wsg_runner_t *r)
{
    if (hal_clock_now_us() >= r->next_deadline_us) {
        (void)advance(r);
    }
    return wsg_runner_poll_advanced(r);
}

uint64_t wsg_runner_poll_advanced(wsg_runner_t *r)
{
    if (hal_clock_now_us() >= r->next_deadline_us) {
        wsg_device_step(r->dev);
    }
    r->next_deadline_us = wsg_device_next_deadline_us(r->dev);
    return r->next_deadline_us;
}

uint64_t wsg_runner_step_now(wsg_runner_t *r)
{
    wsg_runner_due_now(r);
    return wsg_runner_poll(r);
}
