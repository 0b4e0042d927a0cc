/* SPDX-License-Identifier: BSD-3-Clause */
/* The custom commands of the binary interface (spec §4.2, §5): cmd.*, and
 * the byte helpers etob, ntob and bton. The core keeps the ID table and the
 * queue (wsg_script.h); here they meet Lua. */
#include <lauxlib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "script_internal.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_script.h"

#define FLATTEN_DEPTH_MAX 5 /* tables nested in cmd.send's arguments */
#define FRAME_OVERHEAD 8u   /* preamble, ID, length, CRC */

/* An integer 0..255 at index i of the stack, else a Lua error naming `what`. */
static uint8_t check_byte(lua_State *L, int i, const char *what)
{
    int ok = 0;
    lua_Integer v = lua_tointegerx(L, i, &ok);
    if (!ok || v < 0 || v > 255) {
        luaL_error(L, "%s: %s is not an integer 0..255", what, luaL_tolstring(L, i, NULL));
    }
    return (uint8_t)v;
}

static int check_id(lua_State *L, int arg)
{
    lua_Integer id = luaL_checkinteger(L, arg);
    luaL_argcheck(L, id >= 0 && id <= 255, arg, "command ID outside 0..255");
    return (int)id;
}

/* An error naming the ID in hex: lua_pushfstring knows no "%02X". */
static int id_error(lua_State *L, const char *what, int id, const char *why)
{
    char hex[8];
    snprintf(hex, sizeof(hex), "0x%02X", (unsigned)id);
    return luaL_error(L, "%s: ID %s %s", what, hex, why);
}

static int l_register(lua_State *L)
{
    script_t *s = script_of_state(L);
    int id = check_id(L, 1);
    script_host_enter(L);
    wsg_status_t status = wsg_script_register(s->dev, id);
    script_host_leave(L);
    if (status != E_SUCCESS) {
        return id_error(L, "cmd.register", id, "is the firmware's own");
    }
    lua_pushboolean(L, 1);
    return 1;
}

static int l_unregister(lua_State *L)
{
    int id = check_id(L, 1);
    script_host_enter(L);
    wsg_script_unregister(script_of_state(L)->dev, id);
    script_host_leave(L);
    return 0;
}

void script_push_request(lua_State *L, const wsg_script_request_t *req)
{
    lua_pushinteger(L, req->id);
    lua_createtable(L, req->length, 0);
    for (uint16_t k = 0; k < req->length; k++) {
        lua_pushinteger(L, req->payload[k]);
        lua_rawseti(L, -2, k + 1);
    }
}

/* The request the loop took for a waiting cmd.read() (script_service). */
static int read_taken(lua_State *L, int status, lua_KContext ctx)
{
    (void)status;
    (void)ctx;
    script_t *s = script_of_state(L);
    s->has_request = false;
    s->reply_conn = s->request.conn_id;
    script_push_request(L, &s->request);
    return 2;
}

/* cmd.read(): the oldest queued request, or blocks until one comes. */
static int l_read(lua_State *L)
{
    script_t *s = script_of_state(L);
    script_host_enter(L);
    bool taken = wsg_script_take(s->dev, &s->request);
    script_host_leave(L);
    if (taken) {
        return read_taken(L, LUA_OK, 0);
    }
    return script_block(L, "cmd.read", SCRIPT_WAIT_READ, UINT64_MAX, 0, read_taken);
}

static int l_available(lua_State *L)
{
    lua_pushinteger(L, (lua_Integer)wsg_script_pending(script_of_state(L)->dev));
    return 1;
}

static int l_online(lua_State *L)
{
    lua_pushboolean(L, wsg_script_online(script_of_state(L)->dev));
    return 1;
}

static int l_interface(lua_State *L)
{
    script_t *s = script_of_state(L);
    uint64_t host = wsg_script_reply_host(s->dev, s->reply_conn);
    wsg_conn_t *c = host != 0 ? wsg_device_conn_by_id(s->dev, host) : NULL;
    const char *kind = "none";
    if (c != NULL) {
        kind = wsg_conn_transport(c) == WSG_TRANSPORT_DATAGRAM ? "udp" : "tcp";
    }
    lua_pushstring(L, kind);
    return 1;
}

typedef struct {
    uint8_t *out;
    size_t len;
} flat_t;

static void put_byte(lua_State *L, flat_t *f, uint8_t byte)
{
    if (f->len >= SCRIPT_REPLY_MAX) {
        luaL_error(L, "cmd.send: payload longer than %d bytes", (int)SCRIPT_REPLY_MAX);
    }
    f->out[f->len++] = byte;
}

/* One argument at stack index i, by the rules of spec §5.3. */
static void flatten(lua_State *L, flat_t *f, int i, int depth)
{
    switch (lua_type(L, i)) {
    case LUA_TNUMBER:
        put_byte(L, f, check_byte(L, i, "cmd.send"));
        break;
    case LUA_TBOOLEAN:
        put_byte(L, f, (uint8_t)lua_toboolean(L, i));
        break;
    case LUA_TSTRING: {
        size_t len = 0;
        const char *bytes = lua_tolstring(L, i, &len);
        for (size_t k = 0; k < len; k++) {
            put_byte(L, f, (uint8_t)bytes[k]);
        }
        break;
    }
    case LUA_TTABLE: {
        if (depth >= FLATTEN_DEPTH_MAX) {
            luaL_error(L, "cmd.send: tables nested deeper than %d levels", FLATTEN_DEPTH_MAX);
        }
        lua_Integer n = luaL_len(L, i);
        for (lua_Integer k = 1; k <= n; k++) {
            lua_geti(L, i, k);
            flatten(L, f, lua_gettop(L), depth + 1);
            lua_pop(L, 1);
        }
        break;
    }
    default:
        luaL_error(L, "cmd.send: cannot send a %s", luaL_typename(L, i));
    }
}

/* cmd.send(id, ...): one frame, payload exactly the flattened arguments;
 * false when no host can receive it. */
static int l_send(lua_State *L)
{
    script_t *s = script_of_state(L);
    int id = check_id(L, 1);
    if (!wsg_script_registered(s->dev, (uint8_t)id)) {
        return id_error(L, "cmd.send", id, "is not registered");
    }
    if (s->frame == NULL) {
        script_host_enter(L);
        s->frame = malloc(SCRIPT_REPLY_MAX + FRAME_OVERHEAD);
        script_host_leave(L);
        if (s->frame == NULL) {
            return luaL_error(L, "cmd.send: not enough memory");
        }
    }
    /* built where the frame's payload goes: the encoder keeps it in place */
    flat_t f = {s->frame + 6, 0};
    int n = lua_gettop(L);
    for (int i = 2; i <= n; i++) {
        flatten(L, &f, i, 0);
    }
    script_host_enter(L);
    uint64_t host = wsg_script_reply_host(s->dev, s->reply_conn);
    wsg_status_t status = wsg_script_send(s->dev, host, (uint8_t)id, f.out, f.len, s->frame,
                                          SCRIPT_REPLY_MAX + FRAME_OVERHEAD);
    script_host_leave(L);
    lua_pushboolean(L, status == E_SUCCESS);
    return 1;
}

/* etob(code): the status as two bytes, little-endian, in a table. */
static int l_etob(lua_State *L)
{
    lua_Integer code = luaL_checkinteger(L, 1);
    luaL_argcheck(L, code >= 0 && code <= 0xFFFF, 1, "status outside 0..65535");
    lua_createtable(L, 2, 0);
    lua_pushinteger(L, code & 0xFF);
    lua_rawseti(L, -2, 1);
    lua_pushinteger(L, (code >> 8) & 0xFF);
    lua_rawseti(L, -2, 2);
    return 1;
}

/* ntob(x): binary32 little-endian in a table of four bytes; raises for nil. */
static int l_ntob(lua_State *L)
{
    float value = script_check_float(L, 1);
    uint32_t bits;
    memcpy(&bits, &value, sizeof(bits));
    lua_createtable(L, 4, 0);
    for (int k = 0; k < 4; k++) {
        lua_pushinteger(L, (bits >> (8 * k)) & 0xFFu);
        lua_rawseti(L, -2, k + 1);
    }
    return 1;
}

/* bton(t): the inverse of ntob. */
static int l_bton(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TTABLE);
    uint32_t bits = 0;
    for (int k = 0; k < 4; k++) {
        lua_geti(L, 1, k + 1);
        bits |= (uint32_t)check_byte(L, -1, "bton") << (8 * k);
        lua_pop(L, 1);
    }
    float value;
    memcpy(&value, &bits, sizeof(value));
    lua_pushnumber(L, (lua_Number)value);
    return 1;
}

void script_open_cmd(lua_State *L)
{
    static const luaL_Reg cmd[] = {
        {"register", l_register},   {"unregister", l_unregister},
        {"read", l_read},           {"send", l_send},
        {"online", l_online},       {"available", l_available},
        {"interface", l_interface}, {NULL, NULL},
    };
    luaL_newlib(L, cmd);
    lua_setglobal(L, "cmd");
    lua_register(L, "etob", l_etob);
    lua_register(L, "ntob", l_ntob);
    lua_register(L, "bton", l_bton);
}
