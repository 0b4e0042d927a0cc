/* SPDX-License-Identifier: BSD-3-Clause */
/* What every script module stands on (script_internal.h): the script a Lua
 * state runs, blocking calls, float arguments. Below script.c and the
 * bindings, so that calls among the script modules only point down. */
#include <float.h>
#include <lauxlib.h>
#include <math.h>
#include <string.h>

#include "script_internal.h"

script_t *script_of_state(lua_State *L)
{
    script_t *s;
    memcpy(&s, lua_getextraspace(L), sizeof(s));
    return s;
}

int script_block(lua_State *L, const char *name, script_wait_t wait, uint64_t wake_us,
                 lua_KContext ctx, lua_KFunction k)
{
    script_t *s = script_of_state(L);
    if (!lua_isyieldable(L)) {
        /* before the wait is set: Lua's own error here (yield across a C-call
         * boundary), caught by a pcall, left the script parked in that wait */
        return luaL_error(L,
                          "%s: cannot wait inside a function called back from C (a table.sort "
                          "comparator, a __gc finalizer, a gsub replacement)",
                          name);
    }
    if (L != s->co && wait != SCRIPT_WAIT_NONE) {
        /* its own coroutine would yield to the script, not to the device,
         * and leave the main script waiting (docs/scripting.md) */
        return luaL_error(L, "%s: only the main script can wait, not a coroutine of its own", name);
    }
    s->relay = L != s->co; /* sleep(0) there: the whole script yields once */
    s->wait = wait;
    s->wake_us = wake_us;
    return lua_yieldk(L, 0, ctx, k);
}

void script_host_enter(lua_State *L)
{
    script_guard_enter_host(script_of_state(L)->guard);
}

void script_host_leave(lua_State *L)
{
    script_guard_leave_host(script_of_state(L)->guard);
}

float script_check_float(lua_State *L, int arg)
{
    lua_Number v = luaL_checknumber(L, arg);
    if (v > FLT_MAX) {
        return INFINITY;
    }
    if (v < -FLT_MAX) {
        return -INFINITY;
    }
    return (float)v; /* NaN stays NaN */
}
