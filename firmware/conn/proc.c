/* SPDX-License-Identifier: BSD-3-Clause */
/* The command processor under a timing profile (wsg_timing.h): a driver
 * holds a connection's whole request and takes no more of its bytes; the
 * request gets its slot of the processor when it arrives (pace.c) and is
 * run at the slot's end by the driver's serve(), from the connection's
 * serve timer, inside the device's step. Then the port feeds what it kept
 * back (the io's resume()). */
#include <stddef.h>

#include "hal_clock.h"
#include "priv/conn.h"
#include "wsg/wsg_timing.h"

static void serve_due(wsg_timer_t *timer, uint64_t now_us)
{
    (void)now_us;
    conn_t *c = (conn_t *)(void *)((char *)timer - offsetof(conn_t, serve_timer));
    c->request_waits = false;
    c->dev->pace.waiting--;
    c->drv->serve(conn_public(c));
    if (c->open && c->io != NULL && c->io->resume != NULL) {
        c->io->resume(c->io_ctx);
    }
}

void wsg_proc_conn_open(conn_t *c)
{
    c->serve_timer.fire = serve_due;
}

void wsg_proc_conn_close(conn_t *c)
{
    if (c->request_waits) {
        c->request_waits = false;
        c->dev->pace.waiting--;
        wsg_timer_cancel(&c->dev->timers, &c->serve_timer); /* its slot stays spent */
    }
}

void wsg_proc_submit(conn_t *c, wsg_request_kind_t kind)
{
    wsg_dev_t *dev = c->dev;
    uint32_t cost = wsg_rand_service_us(&dev->pace.rng, dev->cfg.timing.service[kind]);
    bool behind_other = false;
    uint64_t done = wsg_pace_reserve(dev, hal_clock_now_us(), cost, c->id, &behind_other);
    c->waited_others += behind_other ? 1u : 0u;
    c->waited_own += c->next_held ? 1u : 0u;
    c->next_held = false;
    c->request_waits = true;
    dev->pace.waiting++;
    wsg_timer_schedule(&dev->timers, &c->serve_timer, done);
}

void wsg_conn_waits(const wsg_conn_t *conn, wsg_conn_waits_t *waits)
{
    const conn_t *c = conn_of_const(conn);
    waits->behind_own = c->waited_own;
    waits->behind_others = c->waited_others;
}

bool wsg_conn_request_waits(const wsg_conn_t *conn)
{
    return conn_of_const(conn)->request_waits;
}
