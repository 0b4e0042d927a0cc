#include "loop.h"

#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <string.h>

#include "log.h"
#include "simclock.h"

typedef struct {
    int fd;
    loop_callback_t callback;
    void *ctx;
} watch_t;

static watch_t watches[LOOP_MAX_WATCHES];
static struct pollfd pollfds[LOOP_MAX_WATCHES];
static unsigned watch_count;
static volatile sig_atomic_t stop_requested;
static sigset_t wait_mask;
static void (*catch_up_fn)(void);
static uint64_t wall_wakeup_ns; /* 0: none */

static void on_signal(int signo)
{
    (void)signo;
    stop_requested = 1;
}

void loop_init(void)
{
    watch_count = 0;
    stop_requested = 0;
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    sigset_t blocked;
    sigemptyset(&blocked);
    sigaddset(&blocked, SIGINT);
    sigaddset(&blocked, SIGTERM);
    sigprocmask(SIG_BLOCK, &blocked, &wait_mask);
    sigdelset(&wait_mask, SIGINT);
    sigdelset(&wait_mask, SIGTERM);
}

void loop_set_catch_up(void (*catch_up)(void))
{
    catch_up_fn = catch_up;
}

bool loop_stop_requested(void)
{
    return stop_requested != 0;
}

void loop_request_stop(void)
{
    stop_requested = 1;
}

static int find(int fd)
{
    for (unsigned i = 0; i < watch_count; i++) {
        if (watches[i].fd == fd) {
            return (int)i;
        }
    }
    return -1;
}

bool loop_watch(int fd, short events, loop_callback_t callback, void *ctx)
{
    if (watch_count == LOOP_MAX_WATCHES) {
        return false;
    }
    watches[watch_count] = (watch_t){fd, callback, ctx};
    pollfds[watch_count] = (struct pollfd){.fd = fd, .events = events, .revents = 0};
    watch_count++;
    return true;
}

void loop_set_events(int fd, short events)
{
    int i = find(fd);
    if (i >= 0) {
        pollfds[i].events = events;
    }
}

void loop_unwatch(int fd)
{
    int i = find(fd);
    if (i < 0) {
        return;
    }
    watch_count--;
    watches[i] = watches[watch_count];
    pollfds[i] = pollfds[watch_count];
}

/* Runs callbacks for the descriptors ppoll() reported. A callback may
 * unwatch descriptors, so each is looked up again by fd. */
static void dispatch(int ready)
{
    int fds[LOOP_MAX_WATCHES];
    short revents[LOOP_MAX_WATCHES];
    unsigned n = 0;
    for (unsigned i = 0; i < watch_count && (int)n < ready; i++) {
        if (pollfds[i].revents != 0) {
            fds[n] = pollfds[i].fd;
            revents[n] = pollfds[i].revents;
            n++;
        }
    }
    for (unsigned k = 0; k < n; k++) {
        int i = find(fds[k]);
        if (i >= 0) {
            watches[i].callback(watches[i].ctx, fds[k], revents[k]);
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

/* ppoll() reports ready descriptors before pending signals, and restores
 * the mask that blocks them on return: under a steady input flood a signal
 * would wait for a quiet moment. Look for it after every wake-up instead. */
static void notice_pending_signals(void)
{
    sigset_t pending;
    if (sigpending(&pending) == 0 &&
        (sigismember(&pending, SIGINT) == 1 || sigismember(&pending, SIGTERM) == 1)) {
        stop_requested = 1;
    }
}

void loop_wait(uint64_t deadline_us)
{
    struct timespec wait = {0, 0};
    bool timed = apply_wall_wakeup(simclock_wall_wait(deadline_us, &wait), &wait);
    int ready = ppoll(pollfds, watch_count, timed ? &wait : NULL, &wait_mask);
    notice_pending_signals();
    if (ready < 0) {
        if (errno != EINTR) {
            host_logf(HAL_LOG_ERROR, "ppoll: %s", strerror(errno));
            loop_request_stop();
        }
        return;
    }
    if (catch_up_fn != NULL) {
        catch_up_fn();
    }
    if (ready > 0) {
        dispatch(ready);
    }
}
