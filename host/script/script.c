/* SPDX-License-Identifier: BSD-3-Clause */
/* The script runtime (script.h): one interpreter per device with a capped
 * allocator, the script as a coroutine, its life cycle and flags, and the
 * resumes the event loop drives. */
#include "script.h"

#include <lauxlib.h>
#include <lualib.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hal_clock.h"
#include "log.h"
#include "script_internal.h"
#include "wsg/wsg_script.h"

script_t *script_create(wsg_device_t *dev, script_guard_t *guard, unsigned index, unsigned devices,
                        const char *store_dir)
{
    script_t *s = calloc(1, sizeof(*s));
    if (s == NULL) {
        return NULL;
    }
    s->dev = dev;
    s->guard = guard;
    s->index = index;
    s->in_fleet = devices > 1;
    if (store_dir != NULL) {
        snprintf(s->store, sizeof(s->store), "%s", store_dir);
    }
    return s;
}

typedef void (*stretch_fn)(script_t *s, void *ctx);

/* Runs fn, which uses the interpreter, as one stretch under the watchdog
 * (script_guard.h); false when the watchdog ended it: the interpreter is
 * left as it was and must be dropped, never touched again. */
static bool run_stretch(script_t *s, stretch_fn fn, void *ctx)
{
    script_guard_t *g = s->guard;
    if (sigsetjmp(*script_guard_exit(g), 0) != 0) {
        script_guard_exited(g);
        return false;
    }
    script_guard_begin(g);
    fn(s, ctx);
    script_guard_end(g);
    return true;
}

/* An error outside any protected call would abort the process: the
 * stretch ends as the watchdog ends it. */
static int on_panic(lua_State *L)
{
    script_guard_abort(script_of_state(L)->guard);
}

static void close_stretch(script_t *s, void *ctx)
{
    (void)ctx;
    lua_close(s->L);
}

/* The interpreter is gone: no wait, no turn, no request left. */
static void clear_state(script_t *s)
{
    s->L = NULL;
    s->co = NULL;
    s->wait = SCRIPT_WAIT_NONE;
    s->preempted = false;
    s->relay = false;
    s->has_request = false;
}

/* Closes the interpreter, running its finalizers under the watchdog; false
 * with *why when they ran too long and it was dropped. */
static bool close_state(script_t *s, char *why, size_t cap)
{
    bool whole = s->L == NULL || run_stretch(s, close_stretch, NULL);
    if (!whole) {
        script_heap_drop(s);
        snprintf(why, cap,
                 "script stopped by the watchdog: its __gc finalizers ran more than %u ms of "
                 "CPU time when it ended",
                 script_guard_watchdog_ms(s->guard));
    }
    clear_state(s);
    return whole;
}

/* Drops it where nobody sees the script's end (a power cycle, the exit):
 * nothing of it runs again, as nothing does on a device that loses its
 * power. Its finalizers would run there with the watchdog's limit each, one
 * device after another: a fleet whose scripts all loop in __gc took 1.6 s
 * to exit for 64 devices, minutes for thousands. */
static void close_quietly(script_t *s)
{
    script_heap_drop(s);
    clear_state(s);
}

void script_destroy(script_t *s)
{
    if (s == NULL) {
        return;
    }
    close_quietly(s);
    script_console_free(s);
    free(s->frame);
    free(s);
}

/* The end, for any reason (spec §2.5): IDs released, queued requests
 * dropped, velocity mode stopped; position motions run to their end. */
static void finish(script_t *s, bool failed, const char *message)
{
    script_console_flush(s);
    char closing[SCRIPT_LINE_MAX];
    if (!close_state(s, closing, sizeof(closing)) && !failed) {
        failed = true; /* its finalizers did not end */
        message = closing;
    }
    if (failed) {
        snprintf(s->error, sizeof(s->error), "%s", message != NULL ? message : "(no message)");
        script_console_line(s, s->error);
        char who[32];
        script_log_name(s, who, sizeof(who));
        host_logf(HAL_LOG_WARN, "%s error: %s", who, s->error);
        s->failure = true;
    }
    s->running = false;
    wsg_script_release_all(s->dev);
    if (wsg_device_velocity_mode(s->dev, NULL)) {
        (void)wsg_op_stop(s->dev);
    }
    wsg_script_set_flags(s->dev, false, s->failure);
}

/* The error object of a failed run as text, without asking Lua to convert
 * it (that allocates: the state may be out of memory). */
static void error_text(lua_State *L, char *out, size_t cap)
{
    switch (lua_type(L, -1)) {
    case LUA_TSTRING:
        snprintf(out, cap, "%s", lua_tostring(L, -1));
        break;
    case LUA_TNUMBER:
        if (lua_isinteger(L, -1)) {
            snprintf(out, cap, "%lld", (long long)lua_tointeger(L, -1));
        } else {
            snprintf(out, cap, "%.14g", (double)lua_tonumber(L, -1));
        }
        break;
    default:
        snprintf(out, cap, "(error object is a %s value)", luaL_typename(L, -1));
    }
}

/* Lua's "not enough memory", with the limit that refused. */
static void explain_memory_error(const script_t *s, char *msg, size_t cap)
{
    if (strcmp(msg, "not enough memory") != 0 || s->refused == SCRIPT_REFUSED_NONE) {
        return;
    }
    if (s->refused == SCRIPT_REFUSED_CAP) {
        snprintf(msg, cap, "not enough memory: the script used its %u MiB",
                 SCRIPT_MEMORY_CAP / (1024u * 1024u));
    } else {
        snprintf(msg, cap,
                 "not enough memory: the scripts of this process used their %zu MiB together",
                 script_guard_memory_budget(s->guard) / (1024u * 1024u));
    }
}

/* The watchdog ended a resume: the interpreter is dropped unseen. */
static void dropped(script_t *s)
{
    script_heap_drop(s);
    s->L = NULL;
    s->co = NULL;
    char msg[SCRIPT_LINE_MAX];
    unsigned ms = script_guard_watchdog_ms(s->guard);
    if (script_guard_exit_reason(s->guard) == SCRIPT_EXIT_PANIC) {
        snprintf(msg, sizeof(msg), "script stopped: an error outside any protected call");
    } else if (!script_guard_last_hook_yieldable(s->guard)) {
        snprintf(msg, sizeof(msg),
                 "script stopped by the watchdog: more than %u ms of CPU time where it cannot "
                 "pause (in a function called back from C, such as a table.sort comparator)",
                 ms);
    } else {
        snprintf(msg, sizeof(msg),
                 "script stopped by the watchdog: more than %u ms of CPU time in one call that "
                 "never pauses (a long pattern match or library call, or a __gc finalizer)",
                 ms);
    }
    finish(s, true, msg);
}

/* A time slice (spec §2.6): every SCRIPT_HOOK_EVERY instructions, yield
 * once the loop pass's slice budget, shared by every script, is spent.
 * Where Lua cannot yield (inside a function called back from C) the run
 * goes on: the watchdog bounds it. */
static void slice_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    script_t *s = script_of_state(L);
    s->kinstr++;
    script_guard_safe_point(s->guard);
    bool yieldable = lua_isyieldable(L);
    script_guard_note_hook(s->guard, yieldable);
    if (!yieldable || !script_guard_slice_over(s->guard)) {
        return;
    }
    s->relay = L != s->co; /* a coroutine of its own: its resumer passes it on */
    (void)lua_yield(L, 0);
}

typedef struct {
    int rc;
    char msg[SCRIPT_LINE_MAX];
} resumed_t;

static void resume_stretch(script_t *s, void *ctx)
{
    resumed_t *r = ctx;
    /* a new count: every resume runs a hook interval before it may yield */
    lua_sethook(s->co, slice_hook, LUA_MASKCOUNT, SCRIPT_HOOK_EVERY);
    int results = 0;
    r->rc = lua_resume(s->co, s->L, 0, &results);
    if (r->rc == LUA_YIELD) {
        lua_pop(s->co, results);
    } else if (r->rc != LUA_OK) {
        error_text(s->co, r->msg, sizeof(r->msg));
    }
}

/* Runs the coroutine until it blocks, ends or its slice is over. */
static void resume(script_t *s)
{
    s->wait = SCRIPT_WAIT_NONE;
    s->preempted = false;
    s->relay = false;
    s->resumes++;
    resumed_t r = {LUA_OK, ""};
    script_guard_slice_start(s->guard);
    bool whole = run_stretch(s, resume_stretch, &r);
    script_guard_slice_end(s->guard);
    if (!whole) {
        dropped(s);
        return;
    }
    if (r.rc == LUA_YIELD) {
        s->preempted = s->wait == SCRIPT_WAIT_NONE;
        script_console_flush(s);
        return;
    }
    explain_memory_error(s, r.msg, sizeof(r.msg));
    finish(s, r.rc != LUA_OK, r.msg);
}

void script_power_on(script_t *s, uint64_t now_us)
{
    s->fingers_ready_us = now_us + SCRIPT_FINGER_STARTUP_US;
}

typedef struct {
    const char *path;
    const char *code;
    size_t len;
    char msg[SCRIPT_LINE_MAX];
} chunk_t;

/* "@name.lua": error messages read "name.lua:28: ..." (spec §2.5). */
static void chunk_name(const char *path, char *out, size_t cap)
{
    const char *slash = strrchr(path, '/');
    snprintf(out, cap, "@%.120s", slash != NULL ? slash + 1 : path);
}

/* The environment and the script's coroutine with the compiled chunk on
 * it, returned (it stays on the state's stack); a protected call. */
static int setup(lua_State *L)
{
    const chunk_t *c = lua_touserdata(L, 1);
    script_open_libs(L);
    script_open_bounded(L);
    script_open_coroutines(L);
    script_open_device(L);
    script_open_cmd(L);
    char name[128];
    chunk_name(c->path, name, sizeof(name));
    if (luaL_loadbufferx(L, c->code, c->len, name, "t") != LUA_OK) {
        return lua_error(L);
    }
    lua_State *co = lua_newthread(L);
    lua_insert(L, -2);
    lua_xmove(L, co, 1); /* the chunk onto the thread */
    return 1;
}

static void open_stretch(script_t *s, void *ctx)
{
    chunk_t *c = ctx;
    s->L = lua_newstate(script_heap_alloc, s);
    if (s->L == NULL) {
        snprintf(c->msg, sizeof(c->msg), "not enough memory for an interpreter");
        return;
    }
    lua_atpanic(s->L, on_panic);
    memcpy(lua_getextraspace(s->L), &s, sizeof(s));
    lua_pushcfunction(s->L, setup);
    lua_pushlightuserdata(s->L, c);
    if (lua_pcall(s->L, 1, 1, 0) != LUA_OK) {
        error_text(s->L, c->msg, sizeof(c->msg));
        return;
    }
    s->co = lua_tothread(s->L, -1);
}

static void start(script_t *s, const char *path, const char *code, size_t len)
{
    chunk_t c = {path, code, len, ""};
    if (!run_stretch(s, open_stretch, &c)) {
        dropped(s);
        return;
    }
    if (s->co == NULL) {
        explain_memory_error(s, c.msg, sizeof(c.msg));
        finish(s, true, c.msg);
        return;
    }
    resume(s);
}

static void set_dir(script_t *s, const char *path)
{
    snprintf(s->dir, sizeof(s->dir), "%s", path);
    char *slash = strrchr(s->dir, '/');
    if (slash != NULL) {
        *slash = '\0';
    } else {
        snprintf(s->dir, sizeof(s->dir), ".");
    }
}

bool script_run(script_t *s, const char *file, char *why, size_t why_cap)
{
    char path[PATH_MAX];
    if (!script_resolve(s, file, true, path, sizeof(path))) {
        snprintf(why, why_cap, "%s: not a script name", file);
        return false;
    }
    if (!script_guard_ready(s->guard, why, why_cap)) {
        return false;
    }
    size_t len = 0;
    char *code = script_read_file(path, &len, why, why_cap);
    if (code == NULL) {
        return false;
    }
    s->start_pending = false; /* a startup script not started yet never is */
    if (s->running) {
        (void)script_stop(s);
    }
    snprintf(s->file, sizeof(s->file), "%s", file);
    set_dir(s, path);
    s->error[0] = '\0';
    s->failure = false;
    s->running = true;
    s->reply_conn = 0;
    s->refused = SCRIPT_REFUSED_NONE;
    wsg_script_release_all(s->dev);
    wsg_script_set_flags(s->dev, true, false);
    char line[SCRIPT_LINE_MAX];
    snprintf(line, sizeof(line), "running %.400s", file);
    script_console_line(s, line);
    start(s, path, code, len);
    free(code);
    return true;
}

/* Why a startup file could not start, named as the user chose it
 * ("/user/NAME"), not by its host path. */
static void startup_refusal(const script_t *s, const char *file, const char *why, char *out,
                            size_t cap)
{
    char path[PATH_MAX];
    if (!script_resolve(s, file, true, path, sizeof(path))) {
        bool no_store = strncmp(file, "/user/", 6) == 0 && s->store[0] == '\0';
        snprintf(out, cap, "startup script %.200s: %s", file,
                 no_store ? "there is no /user/ store (--script-dir)"
                          : "not a store name (/user/NAME.lua)");
        return;
    }
    size_t len = strlen(path);
    bool named = strncmp(why, path, len) == 0 && strncmp(why + len, ": ", 2) == 0;
    snprintf(out, cap, "startup script %.200s: %.200s", file, named ? why + len + 2 : why);
}

void script_run_startup(script_t *s, const char *file)
{
    snprintf(s->pending, sizeof(s->pending), "%s", file);
    s->start_pending = true;
    wsg_script_set_flags(s->dev, true, false); /* it runs from power-on */
}

/* The startup script's start, in the loop's rotation (script_continue). */
static void start_pending(script_t *s)
{
    s->start_pending = false;
    char why[PATH_MAX + 64];
    if (script_run(s, s->pending, why, sizeof(why))) {
        return;
    }
    char message[SCRIPT_LINE_MAX];
    startup_refusal(s, s->pending, why, message, sizeof(message));
    snprintf(s->file, sizeof(s->file), "%s", s->pending);
    finish(s, true, message); /* as a run that failed at once */
}

bool script_stop(script_t *s)
{
    if (s->start_pending) { /* stopped before it started: it never does */
        s->start_pending = false;
        wsg_script_set_flags(s->dev, false, s->failure);
        return true;
    }
    if (!s->running) {
        return false;
    }
    script_console_line(s, "stopped");
    finish(s, false, NULL);
    return true;
}

void script_forget(script_t *s)
{
    script_console_flush(s);
    close_quietly(s);
    s->running = false;
    s->failure = false;
    s->start_pending = false;
}

/* A wake-up that came once the loop pass's budget was spent (script_guard.h):
 * held with the device time (the device stays due now), or left to the
 * preempted scripts' rotation, its request taken for cmd.read(). */
static uint64_t wake_later(script_t *s, uint64_t now)
{
    bool hold = script_guard_holds_time(s->guard);
    script_guard_note_late(s->guard, hold);
    if (hold) {
        return now;
    }
    if (s->wait == SCRIPT_WAIT_READ) {
        s->has_request = wsg_script_take(s->dev, &s->request);
    }
    s->wait = SCRIPT_WAIT_NONE;
    s->preempted = true;
    return UINT64_MAX;
}

uint64_t script_service(script_t *s)
{
    if (!s->running) {
        return UINT64_MAX;
    }
    uint64_t now = hal_clock_now_us();
    bool woken = (s->wait == SCRIPT_WAIT_SLEEP && now >= s->wake_us) ||
                 (s->wait == SCRIPT_WAIT_READ && wsg_script_pending(s->dev) > 0);
    if (woken && script_guard_pass_spent(s->guard)) {
        return wake_later(s, now);
    }
    if (s->wait == SCRIPT_WAIT_SLEEP && now >= s->wake_us) {
        resume(s);
    } else if (s->wait == SCRIPT_WAIT_READ && wsg_script_take(s->dev, &s->request)) {
        s->has_request = true; /* cmd.read() returns it when it runs on */
        resume(s);
    }
    return s->running && s->wait == SCRIPT_WAIT_SLEEP ? s->wake_us : UINT64_MAX;
}

bool script_preempted(const script_t *s)
{
    return s->start_pending || (s->running && s->preempted);
}

bool script_take_turn(script_t *s)
{
    return script_preempted(s) && script_guard_take_turn(s->guard, s->index);
}

void script_continue(script_t *s)
{
    if (s->start_pending) {
        start_pending(s);
    } else if (script_preempted(s)) {
        resume(s);
    }
}

void script_info(const script_t *s, script_info_t *info)
{
    info->file = s->start_pending ? s->pending : s->file;
    info->running = s->running || s->start_pending;
    info->failure = s->failure;
    info->error = s->error;
    info->memory = s->memory;
    info->resumes = s->resumes;
    info->kinstr = s->kinstr;
    script_guard_info(s->guard, &info->process);
}
