/* SPDX-License-Identifier: BSD-3-Clause */
/* User scripts on the gripper (docs/scripting.md): one Lua 5.4 interpreter
 * per device, the script a coroutine resumed by the event loop. It blocks
 * in sleep() and cmd.read() by yielding; its time is the simulated clock; an
 * instruction-count hook ends its time slice, and the process's watchdog
 * (script_guard.h) ends work that cannot pause. A script is a front end of
 * the device like GCL, binary and web: it moves the jaws through the
 * device's operations and answers the custom commands the core queues for
 * it (wsg_script.h). */
#ifndef HOST_SCRIPT_H
#define HOST_SCRIPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "script_guard.h"
#include "wsg/wsg_device.h"

typedef struct script script_t;

/* The interpreter of device `index` (its log prefix "script: " or
 * "script[i]: " in a fleet) under the process's guard; store_dir: the
 * /user/ store (NULL: none). */
script_t *script_create(wsg_device_t *dev, script_guard_t *guard, unsigned index, unsigned devices,
                        const char *store_dir);
void script_destroy(script_t *s);

/* Runs a file (a host path, or /user/NAME in the store): stops a running
 * script first, clears SF_SCRIPT_FAILURE, sets SF_SCRIPT_RUNNING and runs
 * the main chunk until it first blocks. false with *why when the file cannot
 * be read; a file that does not compile starts and fails at once. */
bool script_run(script_t *s, const char *file, char *why, size_t why_cap);
/* The startup script at power-on: SF_SCRIPT_RUNNING at once, the script
 * itself started by the loop in the preempted scripts' rotation
 * (script_take_turn, script_continue), so that no power-on, of one device
 * or of a fleet, waits for scripts. A file that cannot be read then (gone,
 * unreadable, not a store name) fails as a script that fails at once:
 * SF_SCRIPT_FAILURE set, "startup script FILE: reason" as the error, on
 * the console and in the log (warn). The device starts all the same. A
 * script_run() or script_stop() before it started cancels it. */
void script_run_startup(script_t *s, const char *file);
/* The device powered on at now_us: the finger bindings wait until the
 * finger bus has described the fingers (SCRIPT_FINGER_STARTUP_US later). */
void script_power_on(script_t *s, uint64_t now_us);
/* The user stops it: SF_SCRIPT_RUNNING cleared, SF_SCRIPT_FAILURE kept. */
bool script_stop(script_t *s);
/* A power cycle: the device's flags and queue are gone; the interpreter is
 * dropped, nothing of it runs again (no finalizer). script_destroy() drops
 * it the same way. */
void script_forget(script_t *s);

/* Resumes the script if it waits for something that has come (its sleep
 * has ended, a request for cmd.read() is queued). Returns when it must run
 * next on the simulated clock (UINT64_MAX: on an event). */
uint64_t script_service(script_t *s);
/* Its time slice ended while it could run on: the loop continues it
 * (script_continue) when it has its turn (script_take_turn: the preempted
 * scripts of the process share one slice budget per loop pass, in
 * rotation), never blocking in between. */
bool script_preempted(const script_t *s);
bool script_take_turn(script_t *s);
void script_continue(script_t *s);

/* The /user/ store's directory ("" when none), and whether a name is a
 * store file name (NAME.lua: printable ASCII, no '/', no "..", at most 64
 * bytes). */
const char *script_store_dir(const script_t *s);
bool script_store_name_ok(const char *name);

/* Reads a whole script file (a regular file of at most 256 KiB) into a
 * malloc'd, NUL-terminated buffer without ever blocking: it is opened
 * O_NONBLOCK and anything but a regular file (a FIFO, a device, a
 * directory) is refused. NULL with *why ("PATH: reason") when it cannot. */
char *script_read_file(const char *path, size_t *len, char *why, size_t why_cap);

/* What STATE? and the web interface show. */
typedef struct {
    const char *file; /* the last script run, "" when none */
    bool running;
    bool failure;
    const char *error;           /* the last error message, "" when none */
    size_t memory;               /* bytes the interpreter holds */
    uint64_t resumes;            /* times the coroutine was resumed */
    uint64_t kinstr;             /* thousands of VM instructions run (hook counts) */
    script_guard_info_t process; /* what every script of the process shares */
} script_info_t;
void script_info(const script_t *s, script_info_t *info);

/* Console (spec §2.7): the last lines, numbered from 0; *next is the number
 * the next line will get. Returns the lines numbered since.. (at most cap). */
size_t script_console(const script_t *s, uint64_t since, const char **lines, size_t cap,
                      uint64_t *next);

#endif
