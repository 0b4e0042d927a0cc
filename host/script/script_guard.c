/* SPDX-License-Identifier: BSD-3-Clause */
/* The scripts' shared limits (script_guard.h): the watchdog, the slice
 * budget of a loop pass with its rotation, the process's memory budget. */
#include "script_guard.h"

#include <errno.h>
#include <lauxlib.h>
#include <lua.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* The watchdog's limit is measured, not fixed, so that it means the same
 * amount of work on a fast desktop, a slow board, under ASan and under
 * valgrind: WATCHDOG_UNITS times the CPU time the Lua VM takes for the
 * calibration chunk, which adds in a loop and makes small tables (the
 * allocator and the collector run as a script's do: sanitizers and
 * valgrind slow them down more than the VM), within the bounds below.
 * About 20 ms on the 2-core development machine, 50 ms under ASan. */
#define CALIBRATION_CHUNK                                                                          \
    "local x = 0 for i = 1, 200000 do x = x + i end "                                              \
    "for i = 1, 5000 do local t = {i} x = x + #t end return x"
#define CALIBRATION_RUNS 3
#define WATCHDOG_UNITS 26u
#define WATCHDOG_MIN_NS 15000000u      /* 15 ms */
#define WATCHDOG_MAX_NS 10000000000ull /* 10 s */
/* After the first expiry the timer repeats this often, so that an exit
 * that had to wait for host code is taken soon after. */
#define WATCHDOG_REPEAT_NS 1000000u
/* The slice budget of one loop pass, every script together (wall time). */
#define PASS_SLICE_NS 2000000u
/* The memory budget: at least this, more in large fleets. */
#define MEMORY_BUDGET_MIN (64u * 1024u * 1024u)
#define MEMORY_PER_DEVICE (256u * 1024u)

struct script_guard {
    sigjmp_buf exit;
    /* what the signal handler reads and writes */
    volatile sig_atomic_t armed;      /* a stretch runs */
    volatile sig_atomic_t host_depth; /* host code inside it */
    volatile sig_atomic_t pending;    /* an exit waits for the host code's end */
    volatile sig_atomic_t reason;     /* script_exit_t of the last exit */
    volatile sig_atomic_t hook_yieldable;
    uint64_t stretch_cpu_ns; /* the thread's CPU time when the stretch began */
    uint64_t watchdog_ns;    /* 0: not set up yet */
    timer_t timer;
    /* the loop pass */
    uint64_t pass_used_ns; /* script work in this pass so far */
    uint64_t slice_start_ns;
    unsigned first;     /* the device the next pass looks at first */
    unsigned continued; /* preempted scripts continued in this pass */
    unsigned last_turn; /* the device continued last */
    bool hold_time;     /* a late wake-up holds the device time (a paused clock) */
    bool holding;       /* one does in this pass */
    /* memory */
    size_t memory, memory_peak, memory_budget;
    /* figures */
    uint64_t passes, exits, late;
    unsigned most_continued;
};

static uint64_t ns_of(const struct timespec *ts)
{
    return (uint64_t)ts->tv_sec * 1000000000u + (uint64_t)ts->tv_nsec;
}

static struct timespec timespec_of(uint64_t ns)
{
    return (struct timespec){(time_t)(ns / 1000000000u), (long)(ns % 1000000000u)};
}

/* The thread's CPU time (async-signal-safe). */
static uint64_t cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ns_of(&ts);
}

static uint64_t wall_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ns_of(&ts);
}

script_guard_t *script_guard_create(unsigned devices)
{
    script_guard_t *g = calloc(1, sizeof(*g));
    if (g != NULL) {
        size_t per_fleet = (size_t)devices * MEMORY_PER_DEVICE;
        g->memory_budget = per_fleet > MEMORY_BUDGET_MIN ? per_fleet : MEMORY_BUDGET_MIN;
    }
    return g;
}

void script_guard_destroy(script_guard_t *g)
{
    if (g != NULL && g->watchdog_ns != 0) {
        timer_delete(g->timer);
    }
    free(g);
}

static void disarm(script_guard_t *g)
{
    g->armed = 0;
    struct itimerspec off = {{0, 0}, {0, 0}};
    timer_settime(g->timer, 0, &off, NULL); /* async-signal-safe */
}

/* Leaves the stretch for its sigsetjmp(); from the signal handler too. */
static _Noreturn void take_exit(script_guard_t *g, script_exit_t reason)
{
    disarm(g);
    g->reason = (sig_atomic_t)reason;
    g->pending = 0;
    g->host_depth = 0;
    g->exits++;
    siglongjmp(g->exit, 1);
}

/* The timer's signal: the guard comes with it (sival_ptr), no global. A
 * signal of a stretch that has ended, or that comes early, is ignored. */
static void on_watchdog(int signo, siginfo_t *info, void *context)
{
    (void)signo;
    (void)context;
    script_guard_t *g = info->si_code == SI_TIMER ? info->si_value.sival_ptr : NULL;
    if (g == NULL || !g->armed || cpu_ns() - g->stretch_cpu_ns < g->watchdog_ns) {
        return;
    }
    if (g->host_depth > 0) {
        g->pending = 1; /* the allocator or a binding: the next safe point */
        return;
    }
    take_exit(g, SCRIPT_EXIT_WATCHDOG);
}

/* The calibration's allocator: what a script's allocation costs in libc. */
static void *plain_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)ud;
    (void)osize;
    if (nsize == 0) {
        free(ptr);
        return NULL;
    }
    return realloc(ptr, nsize);
}

/* The CPU time of the shortest of a few runs of the calibration chunk. */
static uint64_t calibration_unit(void)
{
    lua_State *L = lua_newstate(plain_alloc, NULL);
    if (L == NULL) {
        return 0;
    }
    uint64_t best = UINT64_MAX;
    if (luaL_loadstring(L, CALIBRATION_CHUNK) == LUA_OK) {
        for (int run = 0; run < CALIBRATION_RUNS; run++) {
            lua_pushvalue(L, -1);
            uint64_t start = cpu_ns();
            lua_call(L, 0, 1);
            uint64_t took = cpu_ns() - start;
            lua_pop(L, 1);
            best = took < best ? took : best;
        }
    }
    lua_close(L);
    return best == UINT64_MAX ? 0 : best;
}

static bool make_timer(script_guard_t *g)
{
    struct sigaction action;
    memset(&action, 0, sizeof(action));
    action.sa_sigaction = on_watchdog;
    action.sa_flags = SA_SIGINFO | SA_RESTART;
    sigemptyset(&action.sa_mask);
    sigset_t watchdog;
    sigemptyset(&watchdog);
    sigaddset(&watchdog, SIGRTMIN);
    struct sigevent event;
    memset(&event, 0, sizeof(event));
    event.sigev_notify = SIGEV_THREAD_ID; /* this thread, the one that runs scripts */
    event.sigev_signo = SIGRTMIN;
    event.sigev_value.sival_ptr = g;
    event._sigev_un._tid = gettid();
    return sigaction(SIGRTMIN, &action, NULL) == 0 &&
           sigprocmask(SIG_UNBLOCK, &watchdog, NULL) == 0 &&
           timer_create(CLOCK_THREAD_CPUTIME_ID, &event, &g->timer) == 0;
}

bool script_guard_ready(script_guard_t *g, char *why, size_t cap)
{
    if (g->watchdog_ns != 0) {
        return true;
    }
    if (!make_timer(g)) {
        snprintf(why, cap, "the script watchdog cannot be set up: %s", strerror(errno));
        return false;
    }
    uint64_t limit = (uint64_t)WATCHDOG_UNITS * calibration_unit();
    g->watchdog_ns = limit < WATCHDOG_MIN_NS   ? WATCHDOG_MIN_NS
                     : limit > WATCHDOG_MAX_NS ? WATCHDOG_MAX_NS
                                               : limit;
    return true;
}

uint32_t script_guard_watchdog_ms(const script_guard_t *g)
{
    return (uint32_t)(g->watchdog_ns / 1000000u);
}

sigjmp_buf *script_guard_exit(script_guard_t *g)
{
    return &g->exit;
}

/* An exit from the signal handler left its signal blocked (the mask was
 * not saved): the next stretch must get it again. */
void script_guard_exited(script_guard_t *g)
{
    (void)g;
    sigset_t watchdog;
    sigemptyset(&watchdog);
    sigaddset(&watchdog, SIGRTMIN);
    sigprocmask(SIG_UNBLOCK, &watchdog, NULL);
}

void script_guard_begin(script_guard_t *g)
{
    g->pending = 0;
    g->host_depth = 0;
    g->reason = SCRIPT_EXIT_NONE;
    g->hook_yieldable = 1;
    g->stretch_cpu_ns = cpu_ns();
    struct itimerspec at = {timespec_of(WATCHDOG_REPEAT_NS), timespec_of(g->watchdog_ns)};
    g->armed = 1;
    timer_settime(g->timer, 0, &at, NULL);
}

void script_guard_end(script_guard_t *g)
{
    disarm(g);
    g->pending = 0;
    g->host_depth = 0;
}

script_exit_t script_guard_exit_reason(const script_guard_t *g)
{
    return (script_exit_t)g->reason;
}

void script_guard_enter_host(script_guard_t *g)
{
    g->host_depth++;
}

void script_guard_leave_host(script_guard_t *g)
{
    g->host_depth--;
}

void script_guard_safe_point(script_guard_t *g)
{
    if (g->pending && g->host_depth == 0 && g->armed) {
        take_exit(g, SCRIPT_EXIT_WATCHDOG);
    }
}

_Noreturn void script_guard_abort(script_guard_t *g)
{
    if (!g->armed) {
        abort(); /* outside a stretch: there is nowhere to go back to */
    }
    take_exit(g, SCRIPT_EXIT_PANIC);
}

void script_guard_note_hook(script_guard_t *g, bool yieldable)
{
    g->hook_yieldable = yieldable;
}

bool script_guard_last_hook_yieldable(const script_guard_t *g)
{
    return g->hook_yieldable != 0;
}

void script_guard_slice_start(script_guard_t *g)
{
    g->slice_start_ns = wall_ns();
}

bool script_guard_slice_over(const script_guard_t *g)
{
    return g->pass_used_ns + (wall_ns() - g->slice_start_ns) >= PASS_SLICE_NS;
}

void script_guard_slice_end(script_guard_t *g)
{
    g->pass_used_ns += wall_ns() - g->slice_start_ns;
}

unsigned script_guard_first(const script_guard_t *g, unsigned devices)
{
    return devices > 0 ? g->first % devices : 0u;
}

bool script_guard_take_turn(script_guard_t *g, unsigned index)
{
    if (g->continued > 0 && g->pass_used_ns >= PASS_SLICE_NS) {
        return false;
    }
    g->continued++;
    g->last_turn = index;
    return true;
}

void script_guard_pass_end(script_guard_t *g)
{
    g->passes++;
    if (g->continued > g->most_continued) {
        g->most_continued = g->continued;
    }
    if (g->continued > 0) {
        g->first = g->last_turn + 1u; /* the next pass starts after it */
    }
    g->continued = 0;
    g->pass_used_ns = 0;
    g->holding = false;
}

bool script_guard_pass_spent(const script_guard_t *g)
{
    return g->pass_used_ns >= PASS_SLICE_NS;
}

void script_guard_set_hold_time(script_guard_t *g, bool hold)
{
    g->hold_time = hold;
}

bool script_guard_holds_time(const script_guard_t *g)
{
    return g->hold_time;
}

void script_guard_note_late(script_guard_t *g, bool held)
{
    g->late++;
    g->holding = g->holding || held;
}

bool script_guard_holding(const script_guard_t *g)
{
    return g->holding;
}

bool script_guard_reserve(script_guard_t *g, size_t more)
{
    if (more > g->memory_budget - g->memory) {
        return false;
    }
    g->memory += more;
    if (g->memory > g->memory_peak) {
        g->memory_peak = g->memory;
    }
    return true;
}

void script_guard_release(script_guard_t *g, size_t less)
{
    g->memory -= less;
}

size_t script_guard_memory_budget(const script_guard_t *g)
{
    return g->memory_budget;
}

void script_guard_info(const script_guard_t *g, script_guard_info_t *info)
{
    *info = (script_guard_info_t){
        .memory = g->memory,
        .memory_peak = g->memory_peak,
        .memory_budget = g->memory_budget,
        .watchdog_ms = script_guard_watchdog_ms(g),
        .slice_us = PASS_SLICE_NS / 1000u,
        .passes = g->passes,
        .most_continued_in_pass = g->most_continued,
        .watchdog_exits = g->exits,
        .late_wakeups = g->late,
    };
}
