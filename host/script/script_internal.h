/* SPDX-License-Identifier: BSD-3-Clause */
/* What the script modules share (the .c files of host/script/): the
 * per-device state and the binding tables. Nothing outside them includes
 * this. */
#ifndef HOST_SCRIPT_INTERNAL_H
#define HOST_SCRIPT_INTERNAL_H

#include <limits.h>
#include <lua.h>
#include <stdbool.h>
#include <stdint.h>

#include "script.h"
#include "script_guard.h"
#include "wsg/wsg_script.h"

#define SCRIPT_MEMORY_CAP (16u * 1024u * 1024u) /* per interpreter (spec §2.6) */
#define SCRIPT_HOOK_EVERY 1000                  /* VM instructions between two hook calls */
#define SCRIPT_CONSOLE_LINES 1000u
/* The bytes of a console's lines, at most: 1000 lines of 64, a fleet's
 * consoles a quarter of the scripts' memory budget (script_guard.c) */
#define SCRIPT_CONSOLE_BYTES (64u * 1024u)
/* The finger bus's start-up after power-on: a node boots in 20 ms, a lost
 * descriptor is asked for again after 100 ms. Finger calls wait for it. */
#define SCRIPT_FINGER_STARTUP_US 100000u
#define SCRIPT_LINE_MAX 512u
#define SCRIPT_REPLY_MAX 65535u /* cmd.send payload (spec §10 #14) */

typedef enum {
    SCRIPT_WAIT_NONE,  /* runnable: its slice ended, or it has not started */
    SCRIPT_WAIT_SLEEP, /* in sleep() until wake_us */
    SCRIPT_WAIT_READ,  /* in cmd.read() */
} script_wait_t;

/* Which limit refused an allocation last (the message of a memory error). */
typedef enum {
    SCRIPT_REFUSED_NONE,
    SCRIPT_REFUSED_CAP,    /* the interpreter's SCRIPT_MEMORY_CAP */
    SCRIPT_REFUSED_BUDGET, /* the process's budget (script_guard.h) */
} script_refused_t;

struct script_block;

struct script {
    wsg_device_t *dev;
    script_guard_t *guard; /* the process's limits */
    unsigned index;
    bool in_fleet;
    char store[PATH_MAX];        /* the /user/ store, "" when none */
    lua_State *L;                /* NULL while no script runs */
    lua_State *co;               /* the script's coroutine */
    struct script_block *blocks; /* every block L holds (script_heap.c) */
    size_t memory;               /* their bytes, the lists' links included */
    script_refused_t refused;
    bool running;
    bool failure;
    bool preempted;
    /* the slice ended inside a coroutine of the script's own: whoever
     * resumed it passes the yield on (script_coro.c) */
    bool relay;
    script_wait_t wait;
    uint64_t wake_us;
    uint64_t fingers_ready_us;    /* finger calls before it wait (script_power_on) */
    wsg_script_request_t request; /* for cmd.read(), taken when it resumes */
    bool has_request;
    uint64_t reply_conn; /* where the request cmd.read() returned last came from */
    char file[PATH_MAX]; /* the script as given */
    /* the startup script, started in the loop's rotation (script_continue) */
    char pending[PATH_MAX];
    bool start_pending;
    char dir[PATH_MAX]; /* its directory: require() looks there first */
    char error[SCRIPT_LINE_MAX];
    char *lines[SCRIPT_CONSOLE_LINES]; /* console ring, line n at n % LINES */
    uint64_t line_first;               /* the oldest line kept */
    uint64_t line_next;
    size_t console_bytes; /* what the kept lines hold, their NULs included */
    char partial[SCRIPT_LINE_MAX];
    size_t partial_len;
    uint8_t *frame; /* cmd.send's frame buffer, SCRIPT_REPLY_MAX + 8 bytes */
    uint64_t resumes;
    uint64_t kinstr;
};

/* script_state.c, below the others: */
/* The script that runs on L (stored in L's extra space). */
script_t *script_of_state(lua_State *L);
/* Argument arg as a float; beyond the float range an infinity. */
float script_check_float(lua_State *L, int arg);
/* Blocking calls (`name` for the error) yield with the wait set; k (may be
 * NULL) runs when the wait is over. Only the main script waits: inside a
 * coroutine of its own they raise an error, except a mere yield
 * (SCRIPT_WAIT_NONE, sleep(0)), which suspends the whole script once.
 * Where Lua cannot yield (a function called back from C) every one of them
 * raises an error, the wait left as it was. */
int script_block(lua_State *L, const char *name, script_wait_t wait, uint64_t wake_us,
                 lua_KContext ctx, lua_KFunction k);
/* Host code inside a binding (a device call, the log, malloc): the
 * watchdog does not end the script in the middle of it. No Lua call, which
 * might raise an error, between the two. */
void script_host_enter(lua_State *L);
void script_host_leave(lua_State *L);

/* script_heap.c: the interpreter's allocator (lua_Alloc, ud the script) */
void *script_heap_alloc(void *ud, void *ptr, size_t osize, size_t nsize);
/* Frees every block L holds without touching L (after a watchdog exit). */
void script_heap_drop(script_t *s);

/* script_coro.c: coroutine.resume and coroutine.wrap that pass a time
 * slice's end on to the host (struct script's relay). */
void script_open_coroutines(lua_State *L);
/* script_bounded.c: string.rep, string.find and table.move with bounds
 * that give a clear error instead of a long stretch without a pause. */
void script_open_bounded(lua_State *L);

/* script_console.c: console output, to the ring and the log */
/* "script" or "script[i]" in a fleet: how the log names the script. */
void script_log_name(const script_t *s, char *out, size_t cap);
void script_console_write(script_t *s, const char *text, size_t len);
void script_console_flush(script_t *s);
void script_console_line(script_t *s, const char *line);
void script_console_free(script_t *s);

/* script_libs.c: the environment (libraries, shims, require, files) */
void script_open_libs(lua_State *L);
/* Resolves a script name or path to a host file: "/user/NAME" and "NAME"
 * (no '/') are in the store; anything else is a host path (only when
 * allow_host). false when the name is not allowed. */
bool script_resolve(const script_t *s, const char *name, bool allow_host, char *out, size_t cap);

/* script_bind.c: globals, mc, gripper, finger, grasping, socket */
void script_open_device(lua_State *L);
/* script_cmd.c: cmd, etob, ntob, bton */
void script_open_cmd(lua_State *L);

/* Pushes id and payload table of a request; for cmd.read() (script_cmd.c). */
void script_push_request(lua_State *L, const wsg_script_request_t *req);

#endif
