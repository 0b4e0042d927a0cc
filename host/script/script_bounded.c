/* SPDX-License-Identifier: BSD-3-Clause */
/* Library functions whose work the instruction hook cannot see (it runs
 * in C), bounded so that the obvious misuses end at once with a clear
 * error rather than after the watchdog's limit (docs/scripting.md,
 * "Limits"): string.rep with an empty unit or a result no script could
 * hold, table.move over more elements than a script's table can hold,
 * and a plain string.find, which searches in linear time here (the
 * library's plain search is quadratic in the worst case). Everything else
 * behaves as the library's function. */
#include <lauxlib.h>
#include <lualib.h>
#include <string.h>

#include "script_internal.h"

/* A script's table holds at most this many elements (16 bytes each). */
#define MOVE_MAX ((lua_Integer)(SCRIPT_MEMORY_CAP / 16u))

/* string.rep(s, n [, sep]): filled by doubling what is written. */
static int l_rep(lua_State *L)
{
    size_t len = 0, sep_len = 0;
    const char *text = luaL_checklstring(L, 1, &len);
    lua_Integer n = luaL_checkinteger(L, 2);
    const char *sep = luaL_optlstring(L, 3, "", &sep_len);
    if (n <= 0 || len + sep_len == 0) {
        lua_pushliteral(L, ""); /* n copies of nothing, however many */
        return 1;
    }
    size_t unit = len + sep_len;
    if (unit < len || (lua_Unsigned)n > SCRIPT_MEMORY_CAP / unit) {
        return luaL_error(L, "string.rep: the result would be larger than a script's %d MiB",
                          (int)(SCRIPT_MEMORY_CAP / (1024u * 1024u)));
    }
    size_t total = (size_t)n * unit - sep_len;
    luaL_Buffer b;
    char *out = luaL_buffinitsize(L, &b, total);
    memcpy(out, text, len);
    size_t filled = len;
    if (filled < total) {
        memcpy(out + filled, sep, sep_len);
        filled += sep_len;
    }
    while (filled < total) {
        size_t more = filled < total - filled ? filled : total - filled;
        memcpy(out + filled, out, more);
        filled += more;
    }
    luaL_pushresultsize(&b, total);
    return 1;
}

/* Calls the library's function (upvalue 1) with this call's arguments. */
static int call_library(lua_State *L)
{
    int n = lua_gettop(L);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, n, LUA_MULTRET);
    return lua_gettop(L);
}

/* table.move(a1, f, e, t [, a2]) */
static int l_move(lua_State *L)
{
    lua_Integer first = luaL_checkinteger(L, 2);
    lua_Integer last = luaL_checkinteger(L, 3);
    /* the count when it cannot overflow; the library reports the rest */
    if (last >= first && (first > 0 || last < LUA_MAXINTEGER + first) && last - first >= MOVE_MAX) {
        return luaL_error(L, "table.move: more elements than a script's table can hold (%d)",
                          (int)MOVE_MAX);
    }
    return call_library(L);
}

/* The pattern has none of Lua's magic characters (lstrlib's nospecials). */
static bool plain_text(const char *pattern, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        if (strchr("^$*+?.([%-", pattern[i]) != NULL && pattern[i] != '\0') {
            return false;
        }
    }
    return true;
}

/* string.find(s, pattern [, init [, plain]]): a plain search with memmem. */
static int l_find(lua_State *L)
{
    size_t len = 0, pattern_len = 0;
    const char *text = luaL_checklstring(L, 1, &len);
    const char *pattern = luaL_checklstring(L, 2, &pattern_len);
    lua_Integer init = luaL_optinteger(L, 3, 1);
    if (!lua_toboolean(L, 4) && !plain_text(pattern, pattern_len)) {
        return call_library(L);
    }
    /* the start as the library clips it (lstrlib's posrelatI), from 0 */
    size_t start = init > 0                   ? (size_t)init - 1u
                   : init == 0                ? 0u
                   : init < -(lua_Integer)len ? 0u
                                              : len + (size_t)init;
    if (start > len) {
        luaL_pushfail(L);
        return 1;
    }
    const char *at = memmem(text + start, len - start, pattern, pattern_len);
    if (at == NULL) {
        luaL_pushfail(L);
        return 1;
    }
    lua_pushinteger(L, (lua_Integer)(at - text) + 1);
    lua_pushinteger(L, (lua_Integer)(at - text) + (lua_Integer)pattern_len);
    return 2;
}

/* table[name] = fn, with the library's table[name] as its upvalue. */
static void replace(lua_State *L, const char *table, const char *name, lua_CFunction fn)
{
    lua_getglobal(L, table);
    lua_getfield(L, -1, name);
    lua_pushcclosure(L, fn, 1);
    lua_setfield(L, -2, name);
    lua_pop(L, 1);
}

void script_open_bounded(lua_State *L)
{
    replace(L, LUA_STRLIBNAME, "rep", l_rep);
    replace(L, LUA_STRLIBNAME, "find", l_find);
    replace(L, LUA_TABLIBNAME, "move", l_move);
}
