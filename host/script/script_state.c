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

int script_block(lua_State *L, script_wait_t wait, uint64_t wake_us)
{
    script_t *s = script_of_state(L);
    s->wait = wait;
    s->wake_us = wake_us;
    return lua_yield(L, 0);
}

int script_block_k(lua_State *L, uint64_t wake_us, lua_KContext ctx, lua_KFunction k)
{
    script_t *s = script_of_state(L);
    s->wait = SCRIPT_WAIT_SLEEP;
    s->wake_us = wake_us;
    return lua_yieldk(L, 0, ctx, k);
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
