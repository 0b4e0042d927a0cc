/* SPDX-License-Identifier: BSD-3-Clause */
/* The single-threaded event loop: file descriptors with callbacks, woken by
 * epoll until the device's next deadline on the simulated clock. A wake-up
 * costs in proportion to the descriptors that are ready, not to those that
 * are watched; with nothing due it sleeps without a timeout. */
#ifndef HOST_LOOP_H
#define HOST_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#include "sim/clock.h"

#define LOOP_MAX_WATCHES 4096 /* --devices 1024: three listeners each, and clients */

typedef void (*loop_callback_t)(void *ctx, int fd, short revents);

/* events and revents are poll()'s bits (POLLIN, POLLOUT, POLLHUP, POLLERR).
 * A callback may unwatch any descriptor, and may watch a new one that got
 * the same number: events reported for the old one are not delivered. */
bool loop_watch(int fd, short events, loop_callback_t callback, void *ctx);
void loop_set_events(int fd, short events);
/* Call before close(fd). */
void loop_unwatch(int fd);

/* Starts afresh (forgets every watch). Blocks SIGINT/SIGTERM/SIGHUP and
 * receives them through a descriptor in the set, so a pending one is noticed
 * at the next wake-up, however busy the loop is. */
void loop_init(void);
/* SIGHUP runs on_hangup (from the loop, not a signal handler); without one
 * SIGHUP is ignored. */
void loop_set_hangup(void (*on_hangup)(void *ctx), void *ctx);
bool loop_stop_requested(void);

/* Runs catch_up(ctx) after every wake-up, before any callback: brings
 * simulated time up to date, so input is handled at the instant it arrived. */
void loop_set_catch_up(void (*catch_up)(void *ctx), void *ctx);
/* loop_wait()'s deadlines are on clock (none set: no deadline is timed). */
void loop_set_clock(const simclock_t *clock);

/* CLOCK_MONOTONIC in ns. */
uint64_t loop_monotonic_ns(void);
/* Makes loop_wait() return by this wall-clock instant at the latest (for
 * back-offs that must not depend on the simulated clock, which may be paused). */
void loop_wake_at_wall(uint64_t monotonic_ns);

/* Waits for events or until simulated time deadline_us, then runs the
 * callbacks of ready descriptors. */
void loop_wait(uint64_t deadline_us);

#endif
