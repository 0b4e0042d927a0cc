/* SPDX-License-Identifier: BSD-3-Clause */
/* The script runtime (script.h): one interpreter per device with a capped
 * allocator, the script as a coroutine, its life cycle and flags, and the
 * resumes the event loop drives. */
#include "script.h"

#include <lauxlib.h>
#include <lualib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "hal_clock.h"
#include "log.h"
#include "script_internal.h"
#include "wsg/wsg_script.h"

static uint64_t wall_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* Lua's allocator with the per-interpreter cap: over it, an allocation
 * fails and Lua raises a memory error. */
static void *capped_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    script_t *s = ud;
    size_t old = ptr != NULL ? osize : 0u;
    if (nsize == 0) {
        free(ptr);
        s->memory -= old;
        return NULL;
    }
    if (nsize > old && s->memory - old + nsize > SCRIPT_MEMORY_CAP) {
        return NULL;
    }
    void *grown = realloc(ptr, nsize);
    if (grown != NULL) {
        s->memory = s->memory - old + nsize;
    }
    return grown;
}

script_t *script_create(wsg_device_t *dev, unsigned index, unsigned devices, const char *store_dir)
{
    script_t *s = calloc(1, sizeof(*s));
    if (s == NULL) {
        return NULL;
    }
    s->dev = dev;
    s->index = index;
    s->in_fleet = devices > 1;
    if (store_dir != NULL) {
        snprintf(s->store, sizeof(s->store), "%s", store_dir);
    }
    return s;
}

static void close_state(script_t *s)
{
    if (s->L != NULL) {
        lua_close(s->L);
        s->L = NULL;
        s->co = NULL;
    }
    s->wait = SCRIPT_WAIT_NONE;
    s->preempted = false;
}

void script_destroy(script_t *s)
{
    if (s == NULL) {
        return;
    }
    close_state(s);
    script_console_free(s);
    free(s->frame);
    free(s);
}

/* The end, for any reason (spec §2.5): IDs released, queued requests
 * dropped, velocity mode stopped; position motions run to their end. */
static void finish(script_t *s, bool failed, const char *message)
{
    script_console_flush(s);
    if (failed) {
        snprintf(s->error, sizeof(s->error), "%s", message != NULL ? message : "(no message)");
        script_console_line(s, s->error);
        char who[32];
        script_log_name(s, who, sizeof(who));
        host_logf(HAL_LOG_WARN, "%s error: %s", who, s->error);
        s->failure = true;
    }
    s->running = false;
    close_state(s);
    wsg_script_release_all(s->dev);
    if (wsg_device_velocity_mode(s->dev, NULL)) {
        (void)wsg_op_stop(s->dev);
    }
    wsg_script_set_flags(s->dev, false, s->failure);
}

/* Runs the coroutine until it blocks, ends or its slice is over. */
static void resume(script_t *s, int nargs)
{
    s->wait = SCRIPT_WAIT_NONE;
    s->preempted = false;
    s->slice_start_ns = wall_ns();
    s->slice_kinstr = 0;
    s->resumes++;
    int results = 0;
    int rc = lua_resume(s->co, s->L, nargs, &results);
    if (rc == LUA_YIELD) {
        lua_pop(s->co, results);
        s->preempted = s->wait == SCRIPT_WAIT_NONE;
        script_console_flush(s);
        return;
    }
    if (rc == LUA_OK) {
        finish(s, false, NULL);
        return;
    }
    const char *msg = lua_tostring(s->co, -1);
    finish(s, true, msg != NULL ? msg : "error object is not a string");
}

/* The time slice (spec §2.6): every SCRIPT_HOOK_EVERY instructions, yield
 * once 2 ms of wall time have passed since the resume. Where a yield is
 * impossible, a run that goes on too long is ended with an error. */
static void slice_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    script_t *s = script_of_state(L);
    s->kinstr++;
    s->slice_kinstr++;
    if (lua_isyieldable(L)) {
        if (wall_ns() - s->slice_start_ns >= SCRIPT_SLICE_NS) {
            (void)lua_yield(L, 0);
        }
        return;
    }
    if (s->slice_kinstr >= SCRIPT_UNYIELDABLE_KINSTR) {
        luaL_error(L, "script ran too long where it cannot yield (inside a C call)");
    }
}

void script_power_on(script_t *s, uint64_t now_us)
{
    s->fingers_ready_us = now_us + SCRIPT_FINGER_STARTUP_US;
}

static lua_State *new_state(script_t *s)
{
    lua_State *L = lua_newstate(capped_alloc, s);
    if (L == NULL) {
        return NULL;
    }
    memcpy(lua_getextraspace(L), &s, sizeof(s));
    script_open_libs(L);
    script_open_device(L);
    script_open_cmd(L);
    return L;
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

/* "@name.lua": error messages read "name.lua:28: ..." (spec §2.5). */
static void chunk_name(const char *path, char *out, size_t cap)
{
    const char *slash = strrchr(path, '/');
    snprintf(out, cap, "@%.120s", slash != NULL ? slash + 1 : path);
}

static void start(script_t *s, const char *path, const char *code, size_t len)
{
    s->L = new_state(s);
    if (s->L == NULL) {
        finish(s, true, "not enough memory for an interpreter");
        return;
    }
    char name[128];
    chunk_name(path, name, sizeof(name));
    if (luaL_loadbufferx(s->L, code, len, name, "t") != LUA_OK) {
        finish(s, true, lua_tostring(s->L, -1));
        return;
    }
    s->co = lua_newthread(s->L);
    lua_insert(s->L, -2);      /* thread below the chunk */
    lua_xmove(s->L, s->co, 1); /* the chunk onto the thread */
    lua_sethook(s->co, slice_hook, LUA_MASKCOUNT, SCRIPT_HOOK_EVERY);
    resume(s, 0);
}

bool script_run(script_t *s, const char *file, char *why, size_t why_cap)
{
    char path[PATH_MAX];
    if (!script_resolve(s, file, true, path, sizeof(path))) {
        snprintf(why, why_cap, "%s: not a script name", file);
        return false;
    }
    size_t len = 0;
    char *code = script_read_file(path, &len, why, why_cap);
    if (code == NULL) {
        return false;
    }
    if (s->running) {
        (void)script_stop(s);
    }
    snprintf(s->file, sizeof(s->file), "%s", file);
    set_dir(s, path);
    s->error[0] = '\0';
    s->failure = false;
    s->running = true;
    s->reply_conn = 0;
    wsg_script_release_all(s->dev);
    wsg_script_set_flags(s->dev, true, false);
    char line[SCRIPT_LINE_MAX];
    snprintf(line, sizeof(line), "running %.400s", file);
    script_console_line(s, line);
    start(s, path, code, len);
    free(code);
    return true;
}

bool script_stop(script_t *s)
{
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
    close_state(s);
    s->running = false;
    s->failure = false;
}

uint64_t script_service(script_t *s)
{
    if (!s->running) {
        return UINT64_MAX;
    }
    uint64_t now = hal_clock_now_us();
    if (s->wait == SCRIPT_WAIT_SLEEP && now >= s->wake_us) {
        resume(s, 0);
    } else if (s->wait == SCRIPT_WAIT_READ && wsg_script_pending(s->dev) > 0) {
        wsg_script_request_t req;
        (void)wsg_script_take(s->dev, &req);
        s->reply_conn = req.conn_id;
        script_push_request(s->co, &req);
        resume(s, 2);
    }
    return s->running && s->wait == SCRIPT_WAIT_SLEEP ? s->wake_us : UINT64_MAX;
}

bool script_preempted(const script_t *s)
{
    return s->running && s->preempted;
}

void script_continue(script_t *s)
{
    if (script_preempted(s)) {
        resume(s, 0);
    }
}

void script_info(const script_t *s, script_info_t *info)
{
    info->file = s->file;
    info->running = s->running;
    info->failure = s->failure;
    info->error = s->error;
    info->memory = s->memory;
    info->resumes = s->resumes;
    info->kinstr = s->kinstr;
}
