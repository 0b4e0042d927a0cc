/* SPDX-License-Identifier: BSD-3-Clause */
/* coroutine.resume and coroutine.wrap for scripts (script_internal.h):
 * the library's, except when the time slice ends inside a coroutine of
 * the script's own. The instruction hook yields that coroutine with the
 * script's relay flag set; its resumer (these functions) then yields in
 * turn, up to the main script and so to the host, and resumes the
 * coroutine again when the script runs next. The script never sees its
 * slice end: a generator's resume does not return early. Where the
 * resumer cannot yield (inside a function called back from C), it resumes
 * the coroutine at once, and the watchdog bounds that stretch. */
#include <lauxlib.h>
#include <lualib.h>

#include "script_internal.h"

/* Upvalue 1 of both: the library's coroutine.resume. */
#define LIBRARY_RESUME lua_upvalueindex(1)
/* Upvalue 2 of a wrapped coroutine's function: the coroutine. */
#define WRAPPED_THREAD lua_upvalueindex(2)

enum { AS_RESUME, AS_WRAP }; /* the continuations' context */

static int resume_again(lua_State *L, int status, lua_KContext how);

/* The stack is [co, what the library's resume returned]: as the library's
 * resume returns it, or as the library's wrap does. */
static int results(lua_State *L, lua_KContext how)
{
    if (how == AS_RESUME) {
        return lua_gettop(L) - 1;
    }
    if (lua_toboolean(L, 2)) {
        return lua_gettop(L) - 2;
    }
    /* an error: the coroutine's to-be-closed variables closed, position
     * added to a text message, as the library's wrap does */
    lua_State *co = lua_tothread(L, 1);
    int status = lua_status(co);
    if (status != LUA_OK && status != LUA_YIELD) {
#if LUA_VERSION_RELEASE_NUM >= 50406
        (void)lua_closethread(co, L);
#else
        (void)lua_resetthread(co);
#endif
    }
    if (lua_type(L, -1) == LUA_TSTRING) {
        luaL_where(L, 1);
        lua_insert(L, -2);
        lua_concat(L, 2);
    }
    return lua_error(L);
}

/* After the library's resume returned: passes a slice's end on. */
static int resumed(lua_State *L, int status, lua_KContext how)
{
    (void)status;
    script_t *s = script_of_state(L);
    while (s->relay) {
        s->relay = false;
        lua_settop(L, 1); /* the coroutine; its yield returned nothing */
        if (lua_isyieldable(L)) {
            s->relay = L != s->co;
            return lua_yieldk(L, 0, how, resume_again);
        }
        script_guard_note_hook(s->guard, false); /* it cannot pause here */
        lua_pushvalue(L, LIBRARY_RESUME);
        lua_pushvalue(L, 1);
        lua_call(L, 1, LUA_MULTRET);
    }
    return results(L, how);
}

/* The script runs again: the coroutine goes on where its slice ended. */
static int resume_again(lua_State *L, int status, lua_KContext how)
{
    (void)status;
    lua_pushvalue(L, LIBRARY_RESUME);
    lua_pushvalue(L, 1);
    lua_callk(L, 1, LUA_MULTRET, how, resumed);
    return resumed(L, LUA_OK, how);
}

/* The stack is [co, args...]: the library's resume on them. */
static int call_resume(lua_State *L, lua_KContext how)
{
    int args = lua_gettop(L) - 1;
    lua_pushvalue(L, LIBRARY_RESUME);
    lua_pushvalue(L, 1);
    lua_rotate(L, 2, 2); /* [co, resume, co, args...] */
    lua_callk(L, args + 1, LUA_MULTRET, how, resumed);
    return resumed(L, LUA_OK, how);
}

/* coroutine.resume(co, ...) */
static int l_resume(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTHREAD);
    return call_resume(L, AS_RESUME);
}

/* The function coroutine.wrap returns. */
static int l_wrapped(lua_State *L)
{
    lua_pushvalue(L, WRAPPED_THREAD);
    lua_insert(L, 1);
    return call_resume(L, AS_WRAP);
}

/* coroutine.wrap(f) */
static int l_wrap(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TFUNCTION);
    lua_State *co = lua_newthread(L);
    lua_pushvalue(L, 1);
    lua_xmove(L, co, 1);
    lua_pushvalue(L, LIBRARY_RESUME);
    lua_insert(L, -2);
    lua_pushcclosure(L, l_wrapped, 2);
    return 1;
}

void script_open_coroutines(lua_State *L)
{
    lua_getglobal(L, LUA_COLIBNAME);
    lua_getfield(L, -1, "resume");
    lua_pushvalue(L, -1);
    lua_pushcclosure(L, l_resume, 1);
    lua_setfield(L, -3, "resume");
    lua_pushcclosure(L, l_wrap, 1);
    lua_setfield(L, -2, "wrap");
    lua_pop(L, 1);
}
