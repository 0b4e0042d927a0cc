/* SPDX-License-Identifier: BSD-3-Clause */
/* The single-threaded event loop: file descriptors with callbacks, woken by
 * epoll until a wall-clock timeout. A wake-up costs in proportion to the
 * descriptors that are ready, not to those that are watched; without a
 * timeout it sleeps until a descriptor or a signal is ready. The loop knows
 * no simulated clock: its owner turns the device's next deadline into a
 * timeout and brings simulated time up to date in the wake hook. */
#ifndef HOST_LOOP_H
#define HOST_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#define LOOP_MAX_WATCHES 4096 /* --devices 1024: three listeners each, and clients */
/* loop_wait()'s timeout when nothing is due: wait for a descriptor or signal. */
#define LOOP_NO_TIMEOUT UINT64_MAX

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
/* Makes the next loop_wait() return by this wall-clock instant at the latest
 * (for back-offs that must not depend on the owner's timeout). */
void loop_wake_at_wall(host_loop_t *loop, uint64_t monotonic_ns);

/* Waits for events, at most timeout_ns of wall-clock time (LOOP_NO_TIMEOUT:
 * no limit), then runs the callbacks of ready descriptors. */
void loop_wait(host_loop_t *loop, uint64_t timeout_ns);

#endif
