/* SPDX-License-Identifier: BSD-3-Clause */
/* The single-threaded event loop: file descriptors with callbacks, woken by
 * epoll until a wall-clock deadline. A wake-up costs in proportion to the
 * descriptors that are ready, not to those that are watched; without a
 * deadline it sleeps until a descriptor or a signal is ready. The deadline
 * is an absolute CLOCK_MONOTONIC instant kept in a timerfd, set again only
 * when it changes, so a wait needs no clock read and a request that moves
 * no deadline costs no timer call. The loop knows no simulated clock: its
 * owner turns the device's next deadline into a wall-clock instant and
 * brings simulated time up to date in the wake hook. */
#ifndef HOST_LOOP_H
#define HOST_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#define LOOP_MAX_WATCHES 4096 /* --devices 1024: three listeners each, and clients */
/* loop_wait()'s deadline when nothing is due: wait for a descriptor or signal. */
#define LOOP_NO_TIMEOUT UINT64_MAX
/* loop_wait()'s deadline when work is left: look at the descriptors, do not sleep. */
#define LOOP_NOW 0u

typedef struct host_loop host_loop_t;

typedef void (*loop_callback_t)(void *ctx, int fd, short revents);
/* A hook of the loop's owner (see loop_set_catch_up, loop_set_hangup). */
typedef void (*loop_hook_t)(void *ctx);

/* A loop with no watches; NULL (logged) when memory or descriptors run out. */
host_loop_t *loop_create(void);
/* Closes the loop's own descriptors; the watched ones stay the callers'. */
void loop_destroy(host_loop_t *loop);
/* Takes the process's signals: ignores SIGPIPE, blocks SIGINT/SIGTERM/SIGHUP
 * and receives them through a descriptor in the loop's set, so a pending one
 * is noticed at the next wake-up, however busy the loop is. Signal
 * disposition is process-wide: one loop takes them (false: logged). */
bool loop_take_signals(host_loop_t *loop);

/* events and revents are poll()'s bits (POLLIN, POLLOUT, POLLHUP, POLLERR).
 * A callback may unwatch any descriptor, and may watch a new one that got
 * the same number: events reported for the old one are not delivered. */
bool loop_watch(host_loop_t *loop, int fd, short events, loop_callback_t callback, void *ctx);
void loop_set_events(host_loop_t *loop, int fd, short events);
/* Call before close(fd). */
void loop_unwatch(host_loop_t *loop, int fd);

/* SIGHUP runs on_hangup(ctx) (from the loop, not a signal handler); without
 * one SIGHUP is ignored. */
void loop_set_hangup(host_loop_t *loop, loop_hook_t on_hangup, void *ctx);
/* SIGINT or SIGTERM arrived, or the loop failed. */
bool loop_stop_requested(const host_loop_t *loop);

/* Runs catch_up(ctx) after every wake-up, before any callback: the owner
 * brings its clock up to date there, so input is handled at the instant it
 * arrived. NULL: none. */
void loop_set_catch_up(host_loop_t *loop, loop_hook_t catch_up, void *ctx);

/* CLOCK_MONOTONIC in ns. */
uint64_t loop_monotonic_ns(void);
/* Makes a loop_wait() return by this wall-clock instant at the latest (for
 * back-offs that must not depend on the owner's deadline); it holds until
 * that instant has come. LOOP_NOW: the next wait does not sleep. */
void loop_wake_at_wall(host_loop_t *loop, uint64_t monotonic_ns);

/* Waits for events until the CLOCK_MONOTONIC instant deadline_ns at the
 * latest (LOOP_NO_TIMEOUT: no limit, LOOP_NOW: no wait), runs the catch-up
 * hook, then the callbacks of ready descriptors. */
void loop_wait(host_loop_t *loop, uint64_t deadline_ns);

#endif
