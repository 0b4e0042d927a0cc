/* SPDX-License-Identifier: BSD-3-Clause */
#include "loop.h"

#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "log.h"

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

struct host_loop {
    watch_t watches[LOOP_MAX_WATCHES];
    int free_slots[LOOP_MAX_WATCHES]; /* stack of free slot numbers */
    int free_count;
    int bucket_head[FD_BUCKETS];
    struct epoll_event ready[LOOP_MAX_WATCHES];
    int epoll_fd;
    int signal_fd;
    int timer_fd;            /* absolute CLOCK_MONOTONIC wake-ups */
    uint64_t timer_armed_ns; /* when it fires; LOOP_NO_TIMEOUT: disarmed */
    bool stop_requested;
    loop_hook_t catch_up;
    void *catch_up_ctx;
    loop_hook_t hangup;
    void *hangup_ctx;
    uint64_t wall_wakeup_ns; /* LOOP_NO_TIMEOUT: none */
};

static int bucket_of(int fd)
{
    return (int)((unsigned)fd % FD_BUCKETS);
}

static int find(const host_loop_t *loop, int fd)
{
    int slot = loop->bucket_head[bucket_of(fd)];
    while (slot != NO_SLOT && loop->watches[slot].fd != fd) {
        slot = loop->watches[slot].next_in_bucket;
    }
    return slot;
}

static void forget_all(host_loop_t *loop)
{
    loop->free_count = 0;
    for (int slot = LOOP_MAX_WATCHES - 1; slot >= 0; slot--) {
        loop->watches[slot].fd = -1;
        loop->free_slots[loop->free_count++] = slot;
    }
    for (int b = 0; b < FD_BUCKETS; b++) {
        loop->bucket_head[b] = NO_SLOT;
    }
}

static void on_signal_fd(void *ctx, int fd, short revents)
{
    host_loop_t *loop = ctx;
    (void)revents;
    struct signalfd_siginfo info;
    while (read(fd, &info, sizeof(info)) == (ssize_t)sizeof(info)) {
        if (info.ssi_signo != SIGHUP) {
            loop->stop_requested = true;
        } else if (loop->hangup != NULL) {
            loop->hangup(loop->hangup_ctx);
        }
    }
}

/* The timer fired: it is disarmed now (one-shot), and a wall-clock wake-up
 * it served is done. */
static void on_timer_fd(void *ctx, int fd, short revents)
{
    host_loop_t *loop = ctx;
    (void)revents;
    uint64_t expirations;
    (void)!read(fd, &expirations, sizeof(expirations));
    if (loop->wall_wakeup_ns <= loop->timer_armed_ns) {
        loop->wall_wakeup_ns = LOOP_NO_TIMEOUT;
    }
    loop->timer_armed_ns = LOOP_NO_TIMEOUT;
}

/* SIGINT, SIGTERM and SIGHUP stay blocked and arrive through a descriptor in
 * the epoll set: a wake-up that reports ready sockets reports a pending
 * signal too, however busy the loop is, and nothing runs in a signal handler. */
bool loop_take_signals(host_loop_t *loop)
{
    signal(SIGPIPE, SIG_IGN);
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    sigprocmask(SIG_BLOCK, &signals, NULL);
    loop->signal_fd = signalfd(-1, &signals, SFD_NONBLOCK | SFD_CLOEXEC);
    if (loop->signal_fd < 0 || !loop_watch(loop, loop->signal_fd, POLLIN, on_signal_fd, loop)) {
        host_logf(HAL_LOG_ERROR, "event loop: cannot receive signals: %s", strerror(errno));
        return false;
    }
    return true;
}

host_loop_t *loop_create(void)
{
    host_loop_t *loop = calloc(1, sizeof(*loop));
    if (loop == NULL) {
        host_logf(HAL_LOG_ERROR, "event loop: %s", strerror(errno));
        return NULL;
    }
    forget_all(loop);
    loop->signal_fd = -1;
    loop->timer_armed_ns = LOOP_NO_TIMEOUT;
    loop->wall_wakeup_ns = LOOP_NO_TIMEOUT;
    loop->epoll_fd = epoll_create1(EPOLL_CLOEXEC);
    loop->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
    if (loop->epoll_fd < 0 || loop->timer_fd < 0 ||
        !loop_watch(loop, loop->timer_fd, POLLIN, on_timer_fd, loop)) {
        host_logf(HAL_LOG_ERROR, "event loop: %s", strerror(errno));
        loop_destroy(loop);
        return NULL;
    }
    return loop;
}

void loop_destroy(host_loop_t *loop)
{
    if (loop == NULL) {
        return;
    }
    if (loop->epoll_fd >= 0) {
        close(loop->epoll_fd);
    }
    if (loop->signal_fd >= 0) {
        close(loop->signal_fd);
    }
    if (loop->timer_fd >= 0) {
        close(loop->timer_fd);
    }
    free(loop);
}

void loop_set_catch_up(host_loop_t *loop, loop_hook_t catch_up, void *ctx)
{
    loop->catch_up = catch_up;
    loop->catch_up_ctx = ctx;
}

void loop_set_hangup(host_loop_t *loop, loop_hook_t on_hangup, void *ctx)
{
    loop->hangup = on_hangup;
    loop->hangup_ctx = ctx;
}

bool loop_stop_requested(const host_loop_t *loop)
{
    return loop->stop_requested;
}

static uint64_t token(const host_loop_t *loop, int slot)
{
    return (uint64_t)loop->watches[slot].generation << 32 | (uint32_t)slot;
}

static int epoll_update(host_loop_t *loop, int op, int slot)
{
    struct epoll_event ev = {.events = (uint32_t)(uint16_t)loop->watches[slot].events,
                             .data.u64 = token(loop, slot)};
    return epoll_ctl(loop->epoll_fd, op, loop->watches[slot].fd, &ev);
}

bool loop_watch(host_loop_t *loop, int fd, short events, loop_callback_t callback, void *ctx)
{
    if (loop->free_count == 0 || loop->epoll_fd < 0) {
        return false;
    }
    int slot = loop->free_slots[--loop->free_count];
    watch_t *w = &loop->watches[slot];
    w->fd = fd;
    w->events = events;
    w->callback = callback;
    w->ctx = ctx;
    if (epoll_update(loop, EPOLL_CTL_ADD, slot) != 0) {
        host_logf(HAL_LOG_ERROR, "event loop: cannot watch descriptor %d: %s", fd, strerror(errno));
        w->fd = -1;
        loop->free_slots[loop->free_count++] = slot;
        return false;
    }
    w->next_in_bucket = loop->bucket_head[bucket_of(fd)];
    loop->bucket_head[bucket_of(fd)] = slot;
    return true;
}

void loop_set_events(host_loop_t *loop, int fd, short events)
{
    int slot = find(loop, fd);
    if (slot == NO_SLOT || loop->watches[slot].events == events) {
        return; /* called for every queued reply: no system call unless it changes */
    }
    loop->watches[slot].events = events;
    epoll_update(loop, EPOLL_CTL_MOD, slot);
}

static void unlink_from_bucket(host_loop_t *loop, int slot)
{
    int *link = &loop->bucket_head[bucket_of(loop->watches[slot].fd)];
    while (*link != slot) {
        link = &loop->watches[*link].next_in_bucket;
    }
    *link = loop->watches[slot].next_in_bucket;
}

void loop_unwatch(host_loop_t *loop, int fd)
{
    int slot = find(loop, fd);
    if (slot == NO_SLOT) {
        return;
    }
    /* fails harmlessly if the caller closed the descriptor first: closing
     * removed it from the set */
    epoll_ctl(loop->epoll_fd, EPOLL_CTL_DEL, fd, NULL);
    unlink_from_bucket(loop, slot);
    loop->watches[slot].fd = -1;
    loop->watches[slot].generation++;
    loop->free_slots[loop->free_count++] = slot;
}

/* Runs the callbacks of the reported descriptors, skipping those a callback
 * unwatched meanwhile (their token's generation is old). */
static void dispatch(host_loop_t *loop, int count)
{
    for (int i = 0; i < count; i++) {
        uint32_t slot = (uint32_t)loop->ready[i].data.u64;
        uint32_t generation = (uint32_t)(loop->ready[i].data.u64 >> 32);
        watch_t *w = &loop->watches[slot];
        if (w->fd >= 0 && w->generation == generation) {
            w->callback(w->ctx, w->fd, (short)(loop->ready[i].events & POLL_BITS));
        }
    }
}

uint64_t loop_monotonic_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

void loop_wake_at_wall(host_loop_t *loop, uint64_t monotonic_ns)
{
    if (monotonic_ns < loop->wall_wakeup_ns) {
        loop->wall_wakeup_ns = monotonic_ns;
    }
}

/* The timer is set only when the instant changes: a request answered at
 * once leaves the next deadline where it was, and costs no system call.
 * False when the timer cannot be set (an instant the kernel refuses). */
static bool arm_timer(host_loop_t *loop, uint64_t deadline_ns)
{
    if (deadline_ns == loop->timer_armed_ns) {
        return true;
    }
    struct itimerspec at = {0}; /* all zero: disarmed */
    if (deadline_ns != LOOP_NO_TIMEOUT) {
        at.it_value.tv_sec = (time_t)(deadline_ns / 1000000000u);
        at.it_value.tv_nsec = (long)(deadline_ns % 1000000000u);
    }
    if (timerfd_settime(loop->timer_fd, TFD_TIMER_ABSTIME, &at, NULL) != 0) {
        host_logf(HAL_LOG_ERROR, "event loop: timer: %s", strerror(errno));
        loop->timer_armed_ns = LOOP_NO_TIMEOUT;
        return false;
    }
    loop->timer_armed_ns = deadline_ns;
    return true;
}

void loop_wait(host_loop_t *loop, uint64_t deadline_ns)
{
    if (loop->wall_wakeup_ns == LOOP_NOW) { /* served by not sleeping */
        loop->wall_wakeup_ns = LOOP_NO_TIMEOUT;
        deadline_ns = LOOP_NOW;
    } else if (loop->wall_wakeup_ns < deadline_ns) {
        deadline_ns = loop->wall_wakeup_ns;
    }
    int timeout_ms = -1;
    if (deadline_ns == LOOP_NOW) {
        timeout_ms = 0;
    } else if (!arm_timer(loop, deadline_ns)) {
        timeout_ms = 1; /* neither sleep past the deadline nor spin */
    }
    int count = epoll_wait(loop->epoll_fd, loop->ready, LOOP_MAX_WATCHES, timeout_ms);
    if (count < 0) {
        if (errno != EINTR) {
            host_logf(HAL_LOG_ERROR, "epoll_wait: %s", strerror(errno));
            loop->stop_requested = true;
        }
        return;
    }
    if (loop->catch_up != NULL) {
        loop->catch_up(loop->catch_up_ctx);
    }
    dispatch(loop, count);
}
