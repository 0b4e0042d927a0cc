/* SPDX-License-Identifier: BSD-3-Clause */
#include "loop.h"

#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include "log.h"
#include "sim/clock.h"

/* The callers speak poll()'s event bits; epoll's have the same values. */
_Static_assert(EPOLLIN == POLLIN && EPOLLOUT == POLLOUT && EPOLLERR == POLLERR &&
                   EPOLLHUP == POLLHUP && EPOLLPRI == POLLPRI,
               "epoll and poll event bits differ");

#define POLL_BITS (EPOLLIN | EPOLLOUT | EPOLLERR | EPOLLHUP | EPOLLPRI)
/* Descriptors are found by fd through a small hash: fd % FD_BUCKETS. */
#define FD_BUCKETS 1024
#define NO_SLOT (-1)

/* A watched descriptor. Its epoll registration carries the slot and the
 * slot's generation, which loop_unwatch() advances: an event that was
 * reported for a descriptor a callback has since unwatched (and perhaps
 * closed, its number reused by a new watch) no longer matches and is
 * dropped instead of reaching the new owner. */
typedef struct {
    int fd; /* -1: free slot */
    uint32_t generation;
    short events;
    loop_callback_t callback;
    void *ctx;
    int next_in_bucket; /* slot, or NO_SLOT */
} watch_t;

static watch_t watches[LOOP_MAX_WATCHES];
static int free_slots[LOOP_MAX_WATCHES]; /* stack of free slot numbers */
static int free_count;
static int bucket_head[FD_BUCKETS];
static struct epoll_event ready[LOOP_MAX_WATCHES];
static int epoll_fd = -1;
static int signal_fd = -1;
static bool stop_requested;
static bool epoll_pwait2_missing; /* kernels before 5.11: millisecond waits */
static void (*catch_up_fn)(void *ctx);
static void *catch_up_ctx;
static const simclock_t *sim_clock; /* what deadlines are measured on */
static void (*hangup_fn)(void *ctx);
static void *hangup_ctx;
static uint64_t wall_wakeup_ns; /* 0: none */

static int bucket_of(int fd)
{
    return (int)((unsigned)fd % FD_BUCKETS);
}

static int find(int fd)
{
    int slot = bucket_head[bucket_of(fd)];
    while (slot != NO_SLOT && watches[slot].fd != fd) {
        slot = watches[slot].next_in_bucket;
    }
    return slot;
}

static void forget_all(void)
{
    free_count = 0;
    for (int slot = LOOP_MAX_WATCHES - 1; slot >= 0; slot--) {
        watches[slot].fd = -1;
        watches[slot].generation++;
        free_slots[free_count++] = slot;
    }
    for (int b = 0; b < FD_BUCKETS; b++) {
        bucket_head[b] = NO_SLOT;
    }
}

static void close_descriptors(void)
{
    if (epoll_fd >= 0) {
        close(epoll_fd);
        epoll_fd = -1;
    }
    if (signal_fd >= 0) {
        close(signal_fd);
        signal_fd = -1;
    }
}

static void on_signal_fd(void *ctx, int fd, short revents)
{
    (void)ctx;
    (void)revents;
    struct signalfd_siginfo info;
    while (read(fd, &info, sizeof(info)) == (ssize_t)sizeof(info)) {
        if (info.ssi_signo != SIGHUP) {
            stop_requested = true;
        } else if (hangup_fn != NULL) {
            hangup_fn(hangup_ctx);
        }
    }
}

/* SIGINT, SIGTERM and SIGHUP stay blocked and arrive through a descriptor in
 * the epoll set: a wake-up that reports ready sockets reports a pending
 * signal too, however busy the loop is, and nothing runs in a signal handler. */
static bool watch_signals(void)
{
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    sigprocmask(SIG_BLOCK, &signals, NULL);
    signal_fd = signalfd(-1, &signals, SFD_NONBLOCK | SFD_CLOEXEC);
    return signal_fd >= 0 && loop_watch(signal_fd, POLLIN, on_signal_fd, NULL);
}

static void loop_request_stop(void)
{
    stop_requested = true;
}

void loop_init(void)
{
    close_descriptors();
    forget_all();
    stop_requested = false;
    wall_wakeup_ns = 0;
    signal(SIGPIPE, SIG_IGN);
    epoll_fd = epoll_create1(EPOLL_CLOEXEC);
    if (epoll_fd < 0 || !watch_signals()) {
        host_logf(HAL_LOG_ERROR, "event loop: %s", strerror(errno));
        loop_request_stop();
    }
}

void loop_set_catch_up(void (*catch_up)(void *ctx), void *ctx)
{
    catch_up_fn = catch_up;
    catch_up_ctx = ctx;
}

void loop_set_clock(const simclock_t *clock)
{
    sim_clock = clock;
}

void loop_set_hangup(void (*on_hangup)(void *ctx), void *ctx)
{
    hangup_fn = on_hangup;
    hangup_ctx = ctx;
}

bool loop_stop_requested(void)
{
    return stop_requested;
}

static uint64_t token(int slot)
{
    return (uint64_t)watches[slot].generation << 32 | (uint32_t)slot;
}

static int epoll_update(int op, int slot)
{
    struct epoll_event ev = {.events = (uint32_t)(uint16_t)watches[slot].events,
                             .data.u64 = token(slot)};
    return epoll_ctl(epoll_fd, op, watches[slot].fd, &ev);
}

bool loop_watch(int fd, short events, loop_callback_t callback, void *ctx)
{
    if (free_count == 0 || epoll_fd < 0) {
        return false;
    }
    int slot = free_slots[--free_count];
    watch_t *w = &watches[slot];
    w->fd = fd;
    w->events = events;
    w->callback = callback;
    w->ctx = ctx;
    if (epoll_update(EPOLL_CTL_ADD, slot) != 0) {
        host_logf(HAL_LOG_ERROR, "event loop: cannot watch descriptor %d: %s", fd, strerror(errno));
        w->fd = -1;
        free_slots[free_count++] = slot;
        return false;
    }
    w->next_in_bucket = bucket_head[bucket_of(fd)];
    bucket_head[bucket_of(fd)] = slot;
    return true;
}

void loop_set_events(int fd, short events)
{
    int slot = find(fd);
    if (slot == NO_SLOT || watches[slot].events == events) {
        return; /* called for every queued reply: no system call unless it changes */
    }
    watches[slot].events = events;
    epoll_update(EPOLL_CTL_MOD, slot);
}

static void unlink_from_bucket(int slot)
{
    int *link = &bucket_head[bucket_of(watches[slot].fd)];
    while (*link != slot) {
        link = &watches[*link].next_in_bucket;
    }
    *link = watches[slot].next_in_bucket;
}

void loop_unwatch(int fd)
{
    int slot = find(fd);
    if (slot == NO_SLOT) {
        return;
    }
    /* fails harmlessly if the caller closed the descriptor first: closing
     * removed it from the set */
    epoll_ctl(epoll_fd, EPOLL_CTL_DEL, fd, NULL);
    unlink_from_bucket(slot);
    watches[slot].fd = -1;
    watches[slot].generation++;
    free_slots[free_count++] = slot;
}

/* Runs the callbacks of the reported descriptors, skipping those a callback
 * unwatched meanwhile (their token's generation is old). */
static void dispatch(int count)
{
    for (int i = 0; i < count; i++) {
        uint32_t slot = (uint32_t)ready[i].data.u64;
        uint32_t generation = (uint32_t)(ready[i].data.u64 >> 32);
        watch_t *w = &watches[slot];
        if (w->fd >= 0 && w->generation == generation) {
            w->callback(w->ctx, w->fd, (short)(ready[i].events & POLL_BITS));
        }
    }
}

uint64_t loop_monotonic_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

void loop_wake_at_wall(uint64_t monotonic_ns)
{
    if (wall_wakeup_ns == 0 || monotonic_ns < wall_wakeup_ns) {
        wall_wakeup_ns = monotonic_ns;
    }
}

/* Shortens the simulated-clock wait to the wall-clock wake-up, if any. */
static bool apply_wall_wakeup(bool timed, struct timespec *wait)
{
    if (wall_wakeup_ns == 0) {
        return timed;
    }
    uint64_t now = loop_monotonic_ns();
    uint64_t left = wall_wakeup_ns > now ? wall_wakeup_ns - now : 0;
    uint64_t current = (uint64_t)wait->tv_sec * 1000000000u + (uint64_t)wait->tv_nsec;
    if (!timed || left < current) {
        wait->tv_sec = (time_t)(left / 1000000000u);
        wait->tv_nsec = (long)(left % 1000000000u);
    }
    if (left == 0) {
        wall_wakeup_ns = 0;
    }
    return true;
}

/* epoll_pwait2() takes a timespec; without it (Linux < 5.11) the wait is
 * rounded up to whole milliseconds, so it never ends before the deadline. */
static int wait_for_events(const struct timespec *wait)
{
    if (!epoll_pwait2_missing) {
        int n = epoll_pwait2(epoll_fd, ready, LOOP_MAX_WATCHES, wait, NULL);
        if (n >= 0 || errno != ENOSYS) {
            return n;
        }
        epoll_pwait2_missing = true;
    }
    int ms = -1;
    if (wait != NULL) {
        uint64_t ns = (uint64_t)wait->tv_sec * 1000000000u + (uint64_t)wait->tv_nsec;
        uint64_t rounded_ms = (ns + 999999u) / 1000000u;
        ms = rounded_ms > (uint64_t)INT32_MAX ? INT32_MAX : (int)rounded_ms;
    }
    return epoll_wait(epoll_fd, ready, LOOP_MAX_WATCHES, ms);
}

void loop_wait(uint64_t deadline_us)
{
    struct timespec wait = {0, 0};
    bool timed = apply_wall_wakeup(
        sim_clock != NULL && simclock_wall_wait(sim_clock, deadline_us, &wait), &wait);
    int count = wait_for_events(timed ? &wait : NULL);
    if (count < 0) {
        if (errno != EINTR) {
            host_logf(HAL_LOG_ERROR, "epoll_wait: %s", strerror(errno));
            loop_request_stop();
        }
        return;
    }
    if (catch_up_fn != NULL) {
        catch_up_fn(catch_up_ctx);
    }
    dispatch(count);
}
