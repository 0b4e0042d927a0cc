/* SPDX-License-Identifier: BSD-3-Clause */
/* What the scripts of one process share (docs/scripting.md, "Limits"):
 *
 * - the watchdog: script work that cannot pause (one long library call, a
 *   __gc finalizer, code called back from C) runs at most
 *   script_guard_watchdog_ms() of CPU time in one stretch. A POSIX timer on
 *   the thread's CPU clock signals; its handler jumps back to where the
 *   stretch began (script_guard_exit()), and the interpreter is dropped
 *   without being touched again. Host code inside a stretch (a binding's
 *   device call, the allocator) marks itself: the exit then waits for the
 *   next safe point (the allocator, the instruction hook, the next tick).
 * - the slice budget of one loop pass, shared by every script, and the
 *   rotation of the preempted scripts each pass continues;
 * - the memory budget of all interpreters together.
 *
 * One per process, owned by the fleet; each script holds a pointer. */
#ifndef HOST_SCRIPT_GUARD_H
#define HOST_SCRIPT_GUARD_H

#include <setjmp.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct script_guard script_guard_t;

/* Why a stretch was ended (script_guard_exit_reason()). */
typedef enum {
    SCRIPT_EXIT_NONE,
    SCRIPT_EXIT_WATCHDOG, /* the timer: no pause for too long */
    SCRIPT_EXIT_PANIC,    /* an error outside any protected call */
} script_exit_t;

/* The memory budget of a fleet of `devices` (docs/scripting.md). */
script_guard_t *script_guard_create(unsigned devices);
void script_guard_destroy(script_guard_t *g);

/* Sets up the watchdog once (its timer, its signal handler, the limit
 * measured on this machine); false with *why when it cannot be had: no
 * script may run then. */
bool script_guard_ready(script_guard_t *g, char *why, size_t cap);
uint32_t script_guard_watchdog_ms(const script_guard_t *g);

/* A stretch of script work: the caller does sigsetjmp(*script_guard_exit(g),
 * 0) in the frame that stays (no signal mask saved: a system call less per
 * stretch), then script_guard_begin(); a return of 1 from sigsetjmp is the
 * exit, after which it calls script_guard_exited() (the guard is idle
 * again). script_guard_end() ends a stretch that returned normally.
 * Stretches do not nest. */
sigjmp_buf *script_guard_exit(script_guard_t *g);
void script_guard_exited(script_guard_t *g);
void script_guard_begin(script_guard_t *g);
void script_guard_end(script_guard_t *g);
script_exit_t script_guard_exit_reason(const script_guard_t *g);
/* Host code inside a stretch: the exit waits until it is left. */
void script_guard_enter_host(script_guard_t *g);
void script_guard_leave_host(script_guard_t *g);
/* A safe point (outside host code): takes an exit the watchdog left pending. */
void script_guard_safe_point(script_guard_t *g);
/* Ends the stretch now as the watchdog would (Lua's panic: an error outside
 * any protected call). Only inside a stretch. */
_Noreturn void script_guard_abort(script_guard_t *g);
/* Notes what the instruction hook found: whether the script could yield
 * there (for the message of a watchdog exit). */
void script_guard_note_hook(script_guard_t *g, bool yieldable);
bool script_guard_last_hook_yieldable(const script_guard_t *g);

/* The slice budget of the loop pass (wall time, every script together). A
 * resume starts its slice (script_guard_slice_start) and ends it; the
 * instruction hook yields once the pass's budget is spent. */
void script_guard_slice_start(script_guard_t *g);
bool script_guard_slice_over(const script_guard_t *g);
void script_guard_slice_end(script_guard_t *g);
/* The pass's continuations of preempted scripts, in rotation: the device
 * to look at first; whether device `index` may continue now (the first of
 * the pass always may, later ones while the budget lasts); the pass's end. */
unsigned script_guard_first(const script_guard_t *g, unsigned devices);
bool script_guard_take_turn(script_guard_t *g, unsigned index);
void script_guard_pass_end(script_guard_t *g);

/* A wake-up (a sleep that ended, a request for a waiting cmd.read()) that
 * comes once the pass's budget is spent waits for a later pass, so that a
 * pass that runs many simulated instants (a catch-up, a STEP) never runs
 * more than its budget of scripts: on a paused clock the device time waits
 * with it (set_hold_time true: a STEP still runs every wake-up at its
 * instant), on a running clock it does not (the script goes on late, in
 * turn with the preempted ones). */
bool script_guard_pass_spent(const script_guard_t *g);
void script_guard_set_hold_time(script_guard_t *g, bool hold);
bool script_guard_holds_time(const script_guard_t *g);
/* A wake-up waited (held: with the device time); holding() until the
 * pass's end: some device's time waits for a later pass. */
void script_guard_note_late(script_guard_t *g, bool held);
bool script_guard_holding(const script_guard_t *g);

/* Memory: whether `more` bytes fit in the process's budget; then they are
 * counted (script_guard_release gives them back). */
bool script_guard_reserve(script_guard_t *g, size_t more);
void script_guard_release(script_guard_t *g, size_t less);
size_t script_guard_memory_budget(const script_guard_t *g);

/* What SCRIPT? shows of the process. */
typedef struct {
    size_t memory;                   /* bytes every interpreter holds */
    size_t memory_peak;              /* the most at any time */
    size_t memory_budget;            /* the budget of them all */
    uint32_t watchdog_ms;            /* 0 until a script ran */
    uint32_t slice_us;               /* the budget of one pass */
    uint64_t passes;                 /* loop passes that looked for scripts */
    unsigned most_continued_in_pass; /* preempted scripts one pass continued, at most */
    uint64_t late_wakeups;           /* wake-ups that waited for a later pass */
    uint64_t watchdog_exits;         /* stretches the watchdog ended */
} script_guard_info_t;
void script_guard_info(const script_guard_t *g, script_guard_info_t *info);

#endif
