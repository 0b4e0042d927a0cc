/* SPDX-License-Identifier: BSD-3-Clause */
/* Feed and step: how a port drives a device. Bytes go in through
 * wsg_runner_feed(); the port polls wsg_runner_poll() when the returned
 * deadline has come (or whenever it wakes) and sleeps until the next one.
 * Shared by the host (one runner per gripper of the fleet) and the board
 * (one in its main loop). The hardware is brought up to the clock before
 * every input and step by the port's advance hook (a simulated world; NULL
 * for hardware that runs by itself). */
#ifndef WSG_RUNNER_H
#define WSG_RUNNER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "wsg_conn.h"

typedef struct {
    wsg_device_t *dev;
    void (*advance)(void *ctx, uint64_t now_us);
    void *advance_ctx;
    uint64_t next_deadline_us; /* when the next step is due */
    /* bytes the last feed took: fewer than given only under a timing
     * profile, when a request waits for the command processor; the port
     * keeps the rest (wsg_conn_input()) */
    size_t taken;
} wsg_runner_t;

/* The first step is due at once (power-on). */
void wsg_runner_init(wsg_runner_t *r, wsg_device_t *dev, void (*advance)(void *ctx, uint64_t now),
                     void *advance_ctx);
/* Feeds bytes to a connection of the device (end_of_datagram: they were a
 * whole datagram). What the input started is due from the next instant on,
 * never at this one: on a paused clock it runs at the next step of time. */
void wsg_runner_feed(wsg_runner_t *r, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                     bool end_of_datagram);
/* The same for a port that polls at the same instant after input, before
 * its clock moves on (the host ticks each touched device in the pass that
 * follows): that poll decides as it would after wsg_runner_feed(), whose
 * deadline (from the next instant on) never makes a step due at this one,
 * and sets the next deadline itself, so it is not worked out here too.
 * Returns whether that poll is needed: false when it would do nothing,
 * that is neither step nor store another deadline (the input was a query,
 * or changed nothing the control step or its deadline depend on), so the
 * port may leave the device alone until its deadline. */
bool wsg_runner_feed_before_poll(wsg_runner_t *r, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                                 bool end_of_datagram);
/* An operation reached the device by another way than its connections (a
 * web page's request): what it started is due from the next instant on, as
 * after wsg_runner_feed(). */
void wsg_runner_input_done(wsg_runner_t *r);
/* Runs the control step if it is due (the hardware brought up to the clock
 * first); returns the next deadline (UINT64_MAX: nothing will change by
 * itself). */
uint64_t wsg_runner_poll(wsg_runner_t *r);
/* The same for a port that brought the hardware up to the clock itself
 * just before (a simulated world it advances at every poll, due or not):
 * the advance hook is not called. */
uint64_t wsg_runner_poll_advanced(wsg_runner_t *r);
/* Runs a control step now (something outside the device changed). */
uint64_t wsg_runner_step_now(wsg_runner_t *r);
/* The step is due now: the next poll runs it (a power-on, a reset). */
void wsg_runner_due_now(wsg_runner_t *r);

#endif
