/* SPDX-License-Identifier: BSD-3-Clause */
/* A script's environment (spec §2.3, §2.4): the standard libraries it may
 * use (no io, os, debug), the 5.1 shims, print and printf to the console,
 * require/dofile/loadfile from the script's directory and the store, and
 * the built-in "socket" module. */
#include <errno.h>
#include <fcntl.h>
#include <lauxlib.h>
#include <lualib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hal_clock.h"
#include "script_internal.h"

#define SCRIPT_FILE_MAX (256u * 1024u)
#define SCRIPT_NAME_MAX 64u
#define CONSOLE_PIECE 4096u /* bytes written between two chances for the watchdog */

/* A store name: a Lua file's plain name, NAME.lua, of printable ASCII, no
 * '/', no "..", at most SCRIPT_NAME_MAX bytes. Only *.lua files are the
 * store's: a configuration, save or log file kept beside the scripts is
 * never a script, never served and never written through the store. */
static bool valid_name(const char *name)
{
    size_t len = strlen(name);
    if (len <= 4 || len > SCRIPT_NAME_MAX || strcmp(name + len - 4, ".lua") != 0 ||
        strstr(name, "..") != NULL) {
        return false;
    }
    for (size_t i = 0; i < len; i++) {
        if (name[i] <= ' ' || name[i] > '~' || name[i] == '/' || name[i] == '\\') {
            return false;
        }
    }
    return true;
}

bool script_store_name_ok(const char *name)
{
    return valid_name(name);
}

const char *script_store_dir(const script_t *s)
{
    return s->store;
}

bool script_resolve(const script_t *s, const char *name, bool allow_host, char *out, size_t cap)
{
    const char *plain = strncmp(name, "/user/", 6) == 0 ? name + 6 : name;
    if (strchr(plain, '/') == NULL) {
        if (!valid_name(plain) || s->store[0] == '\0') {
            return false;
        }
        return (size_t)snprintf(out, cap, "%s/%s", s->store, plain) < cap;
    }
    if (!allow_host || plain != name) {
        return false;
    }
    return (size_t)snprintf(out, cap, "%s", name) < cap;
}

/* Opened without blocking (a FIFO's open would wait for a writer, and the
 * event loop with it), then checked: a regular file or nothing. */
static int open_regular(const char *path, struct stat *st, char *why, size_t why_cap)
{
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        snprintf(why, why_cap, "%s: %s", path, strerror(errno));
        return -1;
    }
    if (fstat(fd, st) != 0 || !S_ISREG(st->st_mode)) {
        snprintf(why, why_cap, "%s: not a regular file", path);
        close(fd);
        return -1;
    }
    if ((size_t)st->st_size > SCRIPT_FILE_MAX) {
        snprintf(why, why_cap, "%s: larger than %u KiB", path, SCRIPT_FILE_MAX / 1024u);
        close(fd);
        return -1;
    }
    return fd;
}

char *script_read_file(const char *path, size_t *len, char *why, size_t why_cap)
{
    struct stat st;
    int fd = open_regular(path, &st, why, why_cap);
    if (fd < 0) {
        return NULL;
    }
    size_t size = (size_t)st.st_size;
    char *code = malloc(size + 1u);
    size_t got = 0;
    while (code != NULL && got < size) {
        ssize_t n = read(fd, code + got, size - got);
        if (n <= 0 && !(n < 0 && errno == EINTR)) {
            break; /* shrunk meanwhile, or a read error */
        }
        got += n > 0 ? (size_t)n : 0u;
    }
    close(fd);
    if (code == NULL || got != size) {
        snprintf(why, why_cap, "%s: cannot read it", path);
        free(code);
        return NULL;
    }
    code[got] = '\0';
    *len = got;
    return code;
}

/* Loads a file as a text chunk named after its base name; pushes the
 * function, or nil and a message. */
static int load_path(lua_State *L, const char *path)
{
    char why[PATH_MAX + 64];
    size_t len = 0;
    script_host_enter(L);
    char *code = script_read_file(path, &len, why, sizeof(why));
    script_host_leave(L);
    if (code == NULL) {
        luaL_pushfail(L);
        lua_pushstring(L, why);
        return 2;
    }
    const char *slash = strrchr(path, '/');
    lua_pushfstring(L, "@%s", slash != NULL ? slash + 1 : path);
    int rc = luaL_loadbufferx(L, code, len, lua_tostring(L, -1), "t");
    free(code);
    lua_remove(L, -2);
    if (rc != LUA_OK) {
        luaL_pushfail(L);
        lua_insert(L, -2);
        return 2;
    }
    return 1;
}

/* loadfile(name): the store only. */
static int l_loadfile(lua_State *L)
{
    const char *name = luaL_checkstring(L, 1);
    char path[PATH_MAX];
    if (!script_resolve(script_of_state(L), name, false, path, sizeof(path))) {
        luaL_pushfail(L);
        lua_pushfstring(L, "%s: not a file of the script store", name);
        return 2;
    }
    return load_path(L, path);
}

static int dofile_done(lua_State *L, int status, lua_KContext base)
{
    (void)status;
    return lua_gettop(L) - (int)base;
}

static int l_dofile(lua_State *L)
{
    int base = lua_gettop(L);
    if (l_loadfile(L) != 1) {
        return lua_error(L);
    }
    lua_callk(L, 0, LUA_MULTRET, base, dofile_done);
    return dofile_done(L, LUA_OK, base);
}

/* require's searcher: NAME.lua in the running script's directory, then in
 * the store (the package.path of spec §2.3). */
static int store_searcher(lua_State *L)
{
    script_t *s = script_of_state(L);
    const char *name = luaL_checkstring(L, 1);
    const char *dirs[2] = {s->dir, s->store};
    char file[SCRIPT_NAME_MAX + 8];
    snprintf(file, sizeof(file), "%s.lua", name);
    if (!valid_name(file)) {
        lua_pushfstring(L, "\n\tno module '%s' (not a script name)", name);
        return 1;
    }
    for (int i = 0; i < 2; i++) {
        char path[PATH_MAX];
        struct stat st;
        if (dirs[i][0] == '\0' ||
            (size_t)snprintf(path, sizeof(path), "%s/%s", dirs[i], file) >= sizeof(path) ||
            stat(path, &st) != 0) {
            continue;
        }
        if (load_path(L, path) != 1) {
            return luaL_error(L, "error loading module '%s': %s", name, lua_tostring(L, -1));
        }
        lua_pushstring(L, path);
        return 2;
    }
    lua_pushfstring(L, "\n\tno file '%s' in the script's directory or the store", file);
    return 1;
}

/* Console output is host code: it logs (script_host_enter); in pieces, so
 * that the watchdog can end a script that prints megabytes of lines. */
static void console_write(lua_State *L, const char *text, size_t len)
{
    script_t *s = script_of_state(L);
    for (size_t done = 0; done < len; done += CONSOLE_PIECE) {
        script_host_enter(L);
        script_console_write(s, text + done,
                             len - done < CONSOLE_PIECE ? len - done : CONSOLE_PIECE);
        script_host_leave(L);
        script_guard_safe_point(s->guard);
    }
}

static int l_print(lua_State *L)
{
    int n = lua_gettop(L);
    for (int i = 1; i <= n; i++) {
        size_t len = 0;
        const char *text = luaL_tolstring(L, i, &len);
        if (i > 1) {
            console_write(L, "\t", 1);
        }
        console_write(L, text, len);
        lua_pop(L, 1);
    }
    console_write(L, "\n", 1);
    return 0;
}

/* printf(fmt, ...): string.format's rules (the library's own function, kept
 * as an upvalue), no newline added. */
static int l_printf(lua_State *L)
{
    int n = lua_gettop(L);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, n, 1);
    size_t len = 0;
    const char *text = lua_tolstring(L, -1, &len);
    console_write(L, text, len);
    return 0;
}

/* load(chunk [, chunkname [, mode [, env]]]): the library's load with
 * mode "t" whatever is asked: text chunks only (precompiled chunks could
 * crash the host). env is passed on only when given, nil included. */
static int l_load(lua_State *L)
{
    int given = lua_gettop(L);
    lua_settop(L, 4); /* the absent arguments as nil, so index 2 is chunkname */
    int top = lua_gettop(L);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_pushvalue(L, 1);
    lua_pushvalue(L, 2);
    lua_pushliteral(L, "t");
    int n = 3;
    if (given >= 4) {
        lua_pushvalue(L, 4);
        n = 4;
    }
    lua_call(L, n, LUA_MULTRET);
    return lua_gettop(L) - top;
}

static int l_math_pow(lua_State *L)
{
    lua_pushnumber(L, pow(luaL_checknumber(L, 1), luaL_checknumber(L, 2)));
    return 1;
}

static int l_table_getn(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    lua_pushinteger(L, (lua_Integer)luaL_len(L, 1));
    return 1;
}

/* socket.gettime(): seconds of simulated time since power-on (spec §4.7). */
static int l_gettime(lua_State *L)
{
    lua_pushnumber(L, (lua_Number)hal_clock_now_us() / 1e6);
    return 1;
}

/* require "socket" returns the module and sets the global socket: UMI's
 * script uses the global (spec §2.3). */
static int open_socket(lua_State *L)
{
    lua_newtable(L);
    lua_pushcfunction(L, l_gettime);
    lua_setfield(L, -2, "gettime");
    lua_pushvalue(L, -1);
    lua_setglobal(L, "socket");
    return 1;
}

static void open_standard(lua_State *L)
{
    static const luaL_Reg libs[] = {
        {LUA_GNAME, luaopen_base},          {LUA_LOADLIBNAME, luaopen_package},
        {LUA_COLIBNAME, luaopen_coroutine}, {LUA_TABLIBNAME, luaopen_table},
        {LUA_STRLIBNAME, luaopen_string},   {LUA_MATHLIBNAME, luaopen_math},
        {LUA_UTF8LIBNAME, luaopen_utf8},
    };
    for (size_t i = 0; i < sizeof(libs) / sizeof(libs[0]); i++) {
        luaL_requiref(L, libs[i].name, libs[i].func, 1);
        lua_pop(L, 1);
    }
}

/* package: the preload searcher and the store searcher; no C modules, and
 * no searchpath: it fopen()s any host path it is given (a FIFO's open
 * waits for a writer, the whole process with it, where no watchdog on CPU
 * time can end it) and tells whether host files exist and can be read. */
static void restrict_package(lua_State *L)
{
    lua_getglobal(L, LUA_LOADLIBNAME);
    lua_pushliteral(L, "");
    lua_setfield(L, -2, "cpath");
    lua_pushliteral(L, "");
    lua_setfield(L, -2, "path");
    lua_pushnil(L);
    lua_setfield(L, -2, "loadlib");
    lua_pushnil(L);
    lua_setfield(L, -2, "searchpath");
    lua_getfield(L, -1, "preload");
    lua_pushcfunction(L, open_socket);
    lua_setfield(L, -2, "socket");
    lua_pop(L, 1);
    lua_getfield(L, -1, "searchers");
    lua_pushcfunction(L, store_searcher);
    lua_rawseti(L, -2, 2);
    for (lua_Integer i = luaL_len(L, -1); i > 2; i--) {
        lua_pushnil(L);
        lua_rawseti(L, -2, i);
    }
    lua_pop(L, 2);
}

static void set_with_upvalue(lua_State *L, const char *table, const char *field, const char *name,
                             lua_CFunction fn)
{
    if (table != NULL) {
        lua_getglobal(L, table);
        lua_getfield(L, -1, field);
        lua_remove(L, -2);
    } else {
        lua_getglobal(L, field);
    }
    lua_pushcclosure(L, fn, 1);
    lua_setglobal(L, name);
}

static void open_shims(lua_State *L)
{
    lua_getglobal(L, LUA_TABLIBNAME);
    lua_getfield(L, -1, "unpack");
    lua_setglobal(L, "unpack");
    lua_pushcfunction(L, l_table_getn);
    lua_setfield(L, -2, "getn");
    lua_pop(L, 1);
    lua_getglobal(L, LUA_MATHLIBNAME);
    lua_pushcfunction(L, l_math_pow);
    lua_setfield(L, -2, "pow");
    lua_pop(L, 1);
    set_with_upvalue(L, NULL, "load", "load", l_load);
    lua_getglobal(L, "load");
    lua_setglobal(L, "loadstring");
}

void script_open_libs(lua_State *L)
{
    open_standard(L);
    restrict_package(L);
    open_shims(L);
    lua_register(L, "print", l_print);
    set_with_upvalue(L, LUA_STRLIBNAME, "format", "printf", l_printf);
    lua_register(L, "loadfile", l_loadfile);
    lua_register(L, "dofile", l_dofile);
}
