/* SPDX-License-Identifier: BSD-3-Clause */
/* The device bindings of a script (spec §4.1, §4.3-§4.6): the E_* status
 * constants, sleep, mc (motion control), gripper, finger and grasping.
 * Motion goes through the device's operations like any front end's; a
 * motion the device refuses returns the status the binary command would
 * answer, never raises; wrong argument types raise. */
#include <lauxlib.h>
#include <float.h>
#include <math.h>

#include "hal_clock.h"
#include "script_internal.h"

static const struct {
    const char *name;
    int code;
} statuses[] = {
    {"E_SUCCESS", 0},
    {"E_NOT_AVAILABLE", 1},
    {"E_NO_SENSOR", 2},
    {"E_NOT_INITIALIZED", 3},
    {"E_ALREADY_RUNNING", 4},
    {"E_FEATURE_NOT_SUPPORTED", 5},
    {"E_INCONSISTENT_DATA", 6},
    {"E_TIMEOUT", 7},
    {"E_READ_ERROR", 8},
    {"E_WRITE_ERROR", 9},
    {"E_INSUFFICIENT_RESOURCES", 10},
    {"E_CHECKSUM_ERROR", 11},
    {"E_NO_PARAM_EXPECTED", 12},
    {"E_NOT_ENOUGH_PARAMS", 13},
    {"E_CMD_UNKNOWN", 14},
    {"E_CMD_FORMAT_ERROR", 15},
    {"E_ACCESS_DENIED", 16},
    {"E_ALREADY_OPEN", 17},
    {"E_CMD_FAILED", 18},
    {"E_CMD_ABORTED", 19},
    {"E_INVALID_HANDLE", 20},
    {"E_NOT_FOUND", 21},
    {"E_NOT_OPEN", 22},
    {"E_IO_ERROR", 23},
    {"E_INVALID_PARAMETER", 24},
    {"E_INDEX_OUT_OF_BOUNDS", 25},
    {"E_CMD_PENDING", 26},
    {"E_OVERRUN", 27},
    {"E_RANGE_ERROR", 28},
    {"RANGE_ERROR", 28}, /* the manual's spelling */
    {"E_AXIS_BLOCKED", 29},
    {"E_FILE_EXISTS", 30},
    {"E_FILE_EXIST", 30},
};

static wsg_device_t *device(lua_State *L)
{
    return script_of_state(L)->dev;
}

static int push_status(lua_State *L, wsg_status_t status)
{
    lua_pushinteger(L, (lua_Integer)status);
    return 1;
}

/* The newest reading, as a GCL query would answer from. */
static const wsg_snapshot_t *snapshot(lua_State *L)
{
    wsg_device_t *dev = device(L);
    script_host_enter(L);
    wsg_device_sense_if_moved_on(dev);
    script_host_leave(L);
    return wsg_device_snapshot(dev);
}

/* The device's operations run as host code (script_host_enter). */
static int push_velocity(lua_State *L, float v)
{
    script_host_enter(L);
    wsg_status_t status = wsg_op_velocity(device(L), v);
    script_host_leave(L);
    return push_status(L, status);
}

static int push_set(lua_State *L, wsg_setting_t which, float value)
{
    script_host_enter(L);
    wsg_status_t status = wsg_op_set(device(L), which, value);
    script_host_leave(L);
    return push_status(L, status);
}

static int push_move(lua_State *L, const wsg_move_args_t *args)
{
    script_host_enter(L);
    wsg_status_t status = wsg_op_move(device(L), NULL, args);
    script_host_leave(L);
    return push_status(L, status);
}

/* A Lua number as a float: beyond the float range it is an infinity
 * (converting it directly would be undefined). */
static float clampf(float v, float low, float high)
{
    return v < low ? low : v > high ? high : v;
}

/* sleep(ms): simulated milliseconds; 0 or less only yields. */
static int l_sleep(lua_State *L)
{
    lua_Number ms = luaL_checknumber(L, 1);
    if (!(ms > 0)) {
        return script_block(L, "sleep", SCRIPT_WAIT_NONE, 0, 0, NULL);
    }
    uint64_t now = hal_clock_now_us();
    lua_Number us = ceil(ms * 1000.0);
    /* beyond the clock's range (sleep(math.huge)): for ever */
    uint64_t wake = us < (lua_Number)(UINT64_MAX - now) ? now + (uint64_t)us : UINT64_MAX;
    return script_block(L, "sleep", SCRIPT_WAIT_SLEEP, wake, 0, NULL);
}

static int l_position(lua_State *L)
{
    lua_pushnumber(L, snapshot(L)->position_mm);
    return 1;
}

/* mc.speed(): the signed measured speed; mc.speed(v): velocity mode. */
static int l_speed(lua_State *L)
{
    if (lua_gettop(L) == 0) {
        lua_pushnumber(L, snapshot(L)->velocity_mm_s);
        return 1;
    }
    float v = script_check_float(L, 1);
    (void)snapshot(L);
    return push_velocity(L, v);
}

static int l_aforce(lua_State *L)
{
    lua_pushnumber(L, snapshot(L)->motor_force_n);
    return 1;
}

/* mc.force(): current force and limit; mc.force(f): the limit, clamped as
 * binary 0x32 clamps it. */
static int l_force(lua_State *L)
{
    const wsg_snapshot_t *snap = snapshot(L);
    if (lua_gettop(L) == 0) {
        lua_pushnumber(L, snap->motor_force_n);
        lua_pushnumber(L, snap->config->default_force_n);
        return 2;
    }
    const wsg_config_t *cfg = snap->config;
    float f = script_check_float(L, 1);
    if (isnan(f)) {
        return push_status(L, E_INVALID_PARAMETER);
    }
    f = clampf(f, cfg->force_min_n, wsg_config_force_max(cfg));
    return push_set(L, WSG_SET_FORCE_LIMIT, f);
}

static int l_blocked(lua_State *L)
{
    uint32_t flags = snapshot(L)->flags;
    lua_pushboolean(L, (flags & (WSG_FLAG(SF_BLOCKED_MINUS) | WSG_FLAG(SF_BLOCKED_PLUS))) != 0u);
    return 1;
}

/* A motion runs, or velocity mode drives (v != 0, not blocked). */
static int l_busy(lua_State *L)
{
    const wsg_snapshot_t *snap = snapshot(L);
    float v = 0.0f;
    bool driving = wsg_device_velocity_mode(device(L), &v) && v != 0.0f && snap->blocked == 0;
    lua_pushboolean(L, snap->motion != WSG_MOTION_NONE || driving);
    return 1;
}

static int l_stop(lua_State *L)
{
    (void)snapshot(L);
    script_host_enter(L);
    wsg_status_t status = wsg_op_stop(device(L));
    script_host_leave(L);
    return push_status(L, status);
}

/* mc.move(width, speed[, flags]): binary 0x21's rules, returns at once. */
static int l_move(lua_State *L)
{
    float width = script_check_float(L, 1);
    float speed = script_check_float(L, 2);
    lua_Integer flags = luaL_optinteger(L, 3, 0);
    const wsg_snapshot_t *snap = snapshot(L);
    const wsg_config_t *cfg = snap->config;
    if (!isfinite(width) || !isfinite(speed)) {
        return push_status(L, E_INVALID_PARAMETER);
    }
    if (flags & 0x01) {
        width += snap->position_mm;
    }
    width = clampf(width, 0.0f, cfg->stroke_mm);
    if (!wsg_config_target_ok(cfg, width)) {
        return push_status(L, E_RANGE_ERROR);
    }
    if (snap->motion != WSG_MOTION_NONE) {
        return push_status(L, E_ALREADY_RUNNING);
    }
    wsg_move_args_t args = {width, clampf(fabsf(speed), cfg->speed_min_mm_s, cfg->speed_max_mm_s),
                            false, (flags & 0x02) != 0};
    return push_move(L, &args);
}

/* mc.homing([dir]): 0 or nil (or a boolean) the configured direction, 1
 * opening, 2 closing. */
static int l_homing(lua_State *L)
{
    lua_Integer dir = lua_isinteger(L, 1) ? lua_tointeger(L, 1) : 0;
    if (!lua_isnoneornil(L, 1) && !lua_isboolean(L, 1) && !lua_isinteger(L, 1)) {
        return luaL_typeerror(L, 1, "integer");
    }
    if (dir < 0 || dir > 2) {
        return push_status(L, E_INVALID_PARAMETER);
    }
    (void)snapshot(L);
    wsg_home_args_t args = {(wsg_home_dir_t)dir};
    script_host_enter(L);
    wsg_status_t status = wsg_op_home(device(L), NULL, &args);
    script_host_leave(L);
    return push_status(L, status);
}

/* mc.acceleration([a]): get, or set like binary 0x30 (clamped). */
static int l_acceleration(lua_State *L)
{
    const wsg_config_t *cfg = snapshot(L)->config;
    if (lua_gettop(L) == 0) {
        lua_pushnumber(L, cfg->default_accel_mm_s2);
        return 1;
    }
    float a = script_check_float(L, 1);
    if (isnan(a)) {
        return push_status(L, E_INVALID_PARAMETER);
    }
    a = clampf(a, cfg->accel_min_mm_s2, cfg->accel_max_mm_s2);
    return push_set(L, WSG_SET_ACCEL, a);
}

static int l_state(lua_State *L)
{
    lua_pushinteger(L, (lua_Integer)snapshot(L)->flags);
    return 1;
}

static int finger_count(lua_State *L);
static int finger_type(lua_State *L);
static int finger_data(lua_State *L);
static const lua_CFunction finger_queries[] = {finger_count, finger_type, finger_data};
static const char *const finger_query_names[] = {"finger.count", "finger.type", "finger.data"};

static int finger_query_again(lua_State *L, int status, lua_KContext which)
{
    (void)status;
    return finger_queries[which](L);
}

/* Runs finger query `which`, after the finger bus's start-up: a startup
 * script that counts its fingers at once sees them (wsg50-ros-pkg's does). */
static int finger_query(lua_State *L, lua_KContext which)
{
    script_t *s = script_of_state(L);
    uint64_t now = hal_clock_now_us();
    if (now < s->fingers_ready_us) {
        return script_block(L, finger_query_names[which], SCRIPT_WAIT_SLEEP, s->fingers_ready_us,
                            which, finger_query_again);
    }
    return finger_queries[which](L);
}

static int check_finger(lua_State *L)
{
    lua_Integer i = luaL_checkinteger(L, 1);
    luaL_argcheck(L, i >= 0 && i < WSG_FINGER_COUNT, 1, "finger index outside 0..1");
    return (int)i;
}

static int finger_count(lua_State *L)
{
    lua_pushinteger(L, WSG_FINGER_COUNT);
    return 1;
}

static int finger_type(lua_State *L)
{
    int i = check_finger(L);
    lua_pushstring(L, wsg_finger_type_name(snapshot(L)->fingers->slot[i].type));
    return 1;
}

/* DSA: {frame = {row1, ..., row14}}, each row 6 raw cells. */
static void push_dsa_frame(lua_State *L, const wsg_finger_t *f)
{
    lua_createtable(L, 0, 1);
    lua_createtable(L, 14, 0);
    for (int row = 0; row < 14; row++) {
        lua_createtable(L, 6, 0);
        for (int col = 0; col < 6; col++) {
            int k = row * 6 + col;
            lua_pushinteger(L, k < f->data_count ? (lua_Integer)f->data[k] : 0);
            lua_rawseti(L, -2, col + 1);
        }
        lua_rawseti(L, -2, row + 1);
    }
    lua_setfield(L, -2, "frame");
}

/* FMF: the force (FDATA); DSA: a frame; generic or none: nil. */
static int finger_data(lua_State *L)
{
    int i = check_finger(L);
    const wsg_finger_t *f = &snapshot(L)->fingers->slot[i];
    if (f->type == FINGER_FMF && f->data_count > 0) {
        lua_pushnumber(L, f->data[0]);
    } else if (f->type == FINGER_DSA) {
        push_dsa_frame(L, f);
    } else {
        lua_pushnil(L);
    }
    return 1;
}

static int l_finger_count(lua_State *L)
{
    return finger_query(L, 0);
}

static int l_finger_type(lua_State *L)
{
    return finger_query(L, 1);
}

static int l_finger_data(lua_State *L)
{
    return finger_query(L, 2);
}

/* Finger I/O for generic fingers: wsgsim simulates none (spec §4.5). */
static int l_finger_power(lua_State *L)
{
    (void)check_finger(L);
    return push_status(L, E_SUCCESS);
}

static int l_finger_interface(lua_State *L)
{
    (void)check_finger(L);
    return push_status(L, E_FEATURE_NOT_SUPPORTED);
}

static int l_finger_write(lua_State *L)
{
    (void)check_finger(L);
    return push_status(L, E_SUCCESS);
}

static int l_finger_read(lua_State *L)
{
    (void)check_finger(L);
    lua_newtable(L);
    return 1;
}

static int l_finger_bytes_available(lua_State *L)
{
    (void)check_finger(L);
    lua_pushinteger(L, 0);
    return 1;
}

static int l_finger_spi(lua_State *L)
{
    (void)check_finger(L);
    luaL_checktype(L, 2, LUA_TTABLE);
    lua_Integer n = luaL_len(L, 2);
    lua_createtable(L, (int)(n > 0 ? n : 0), 0);
    for (lua_Integer k = 1; k <= n; k++) {
        lua_pushinteger(L, 0);
        lua_rawseti(L, -2, k);
    }
    return 1;
}

/* grasping.grasp(width, speed[, force]): a grip like GCL GRIP(width, speed). */
static int l_grasp(lua_State *L)
{
    float width = script_check_float(L, 1);
    float speed = script_check_float(L, 2);
    const wsg_config_t *cfg = snapshot(L)->config;
    float force = lua_isnumber(L, 3) ? script_check_float(L, 3) : cfg->default_force_n;
    wsg_grip_args_t args = {force, true, width, speed, cfg->default_pwt_mm, cfg->default_clt_mm};
    script_host_enter(L);
    wsg_status_t status = wsg_op_grip(device(L), NULL, &args);
    script_host_leave(L);
    return push_status(L, status);
}

static int l_grasping_move(lua_State *L)
{
    float width = script_check_float(L, 1);
    float speed = script_check_float(L, 2);
    (void)snapshot(L);
    wsg_move_args_t args = {width, speed, false, false};
    return push_move(L, &args);
}

static int l_grasping_state(lua_State *L)
{
    lua_pushinteger(L, (lua_Integer)snapshot(L)->grip_state);
    return 1;
}

static int l_not_supported(lua_State *L)
{
    return push_status(L, E_FEATURE_NOT_SUPPORTED);
}

static void open_table(lua_State *L, const char *name, const luaL_Reg *fns)
{
    lua_newtable(L);
    luaL_setfuncs(L, fns, 0);
    lua_setglobal(L, name);
}

void script_open_device(lua_State *L)
{
    for (size_t i = 0; i < sizeof(statuses) / sizeof(statuses[0]); i++) {
        lua_pushinteger(L, statuses[i].code);
        lua_setglobal(L, statuses[i].name);
    }
    lua_register(L, "sleep", l_sleep);
    static const luaL_Reg mc[] = {
        {"position", l_position},
        {"speed", l_speed},
        {"aforce", l_aforce},
        {"force", l_force},
        {"blocked", l_blocked},
        {"busy", l_busy},
        {"stop", l_stop},
        {"move", l_move},
        {"homing", l_homing},
        {"acceleration", l_acceleration},
        {NULL, NULL},
    };
    open_table(L, "mc", mc);
    static const luaL_Reg gripper[] = {{"state", l_state}, {NULL, NULL}};
    open_table(L, "gripper", gripper);
    static const luaL_Reg finger[] = {
        {"count", l_finger_count},
        {"type", l_finger_type},
        {"data", l_finger_data},
        {"power", l_finger_power},
        {"interface", l_finger_interface},
        {"write", l_finger_write},
        {"read", l_finger_read},
        {"bytes_available", l_finger_bytes_available},
        {"spi", l_finger_spi},
        {NULL, NULL},
    };
    open_table(L, "finger", finger);
    static const luaL_Reg grasping[] = {
        {"grasp", l_grasp},         {"move", l_grasping_move},          {"state", l_grasping_state},
        {"clamp", l_not_supported}, {"stop_clamping", l_not_supported}, {NULL, NULL},
    };
    open_table(L, "grasping", grasping);
}
