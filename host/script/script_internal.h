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
#include "wsg/wsg_script.h"

#define SCRIPT_MEMORY_CAP (16u * 1024u * 1024u) /* per interpreter (spec §2.6) */
#define SCRIPT_HOOK_EVERY 1000                  /* VM instructions between two hook calls */
#define SCRIPT_SLICE_NS 2000000u                /* a resume yields after 2 ms of wall time */
/* A run that cannot yield (inside a C function's callback, a metamethod)
 * and has executed this many thousand instructions is ended with an error:
 * the loop must not freeze. About a second of work. */
#define SCRIPT_UNYIELDABLE_KINSTR 100000u
#define SCRIPT_CONSOLE_LINES 1000u
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

struct script {
    wsg_device_t *dev;
    unsigned index;
    bool in_fleet;
    char store[PATH_MAX]; /* the /user/ store, "" when none */
    lua_State *L;         /* NULL while no script runs */
    lua_State *co;        /* the script's coroutine */
    size_t memory;        /* bytes allocated by L */
    bool running;
    bool failure;
    bool preempted;
    script_wait_t wait;
    uint64_t wake_us;
    uint64_t fingers_ready_us; /* finger calls before it wait (script_power_on) */
    uint64_t slice_start_ns;
    uint64_t slice_kinstr;
    uint64_t reply_conn; /* where the request cmd.read() returned last came from */
    char file[PATH_MAX]; /* the script as given */
    char dir[PATH_MAX];  /* its directory: require() looks there first */
    char error[SCRIPT_LINE_MAX];
    char *lines[SCRIPT_CONSOLE_LINES]; /* console ring, line n at n % LINES */
    uint64_t line_next;
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
/* Blocking calls yield with the wait set. */
int script_block(lua_State *L, script_wait_t wait, uint64_t wake_us);
/* The same, for a binding that runs again (k) when the wait is over. */
int script_block_k(lua_State *L, uint64_t wake_us, lua_KContext ctx, lua_KFunction k);

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
/* Reads a whole file (at most 256 KiB) into a malloc'd buffer. */
char *script_read_file(const char *path, size_t *len, char *why, size_t why_cap);

/* script_bind.c: globals, mc, gripper, finger, grasping, socket */
void script_open_device(lua_State *L);
/* script_cmd.c: cmd, etob, ntob, bton */
void script_open_cmd(lua_State *L);

/* Pushes id and payload table of a request; for cmd.read() (script_cmd.c). */
void script_push_request(lua_State *L, const wsg_script_request_t *req);

#endif
