/* SPDX-License-Identifier: BSD-3-Clause */
#include "gripper.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "can_loopback.h"
#include "config_file.h"
#include "hal_clock.h"
#include "log.h"
#include "run_seed.h"
#include "physics_setup.h"
#include "plant_socket.h"
#include "script.h"
#include "script_options.h"
#include "sim/sim_models.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_gcl.h"

/* What a connection opened without a driver (--protocol auto) may speak:
 * the binary protocol claims its preamble byte, GCL everything else. */
static const wsg_proto_driver_t *const host_drivers[] = {&wsg_bin_driver, &wsg_gcl_driver};

/* A part given at start sits between the jaws: open them beyond it. */
static void place_start_part(gripper_t *g)
{
    sim_axis_t *axis = &g->world.axis;
    const host_options_t *opts = g->opts;
    if (opts->part_width_mm >= axis->stroke_mm) {
        host_logf(HAL_LOG_WARN, "part of %.1f mm does not fit a %.0f mm stroke; ignored",
                  (double)opts->part_width_mm, (double)axis->stroke_mm);
        return;
    }
    if (axis->x_mm <= opts->part_width_mm) {
        wsg_sim_axis_place_jaws(axis, axis->stroke_mm);
    }
    wsg_sim_axis_place_part(axis, opts->part_width_mm, opts->part_stiffness_n_mm);
}

static void power_on_world(gripper_t *g)
{
    g->powered_on_us = hal_clock_now_us();
    wsg_sim_world_init(&g->world, &g->config, g->powered_on_us);
    if (g->physics != NULL) {
        physics_world_power_on(g->physics, g->powered_on_us);
    } else if (g->opts->part_given) {
        place_start_part(g);
    }
    wsg_runner_due_now(&g->runner);
}

/* The runner's hook, before every input: the world is mostly current
 * then (an input between two steps), and that is decided without the
 * registers the advance itself saves (its time step is inline). */
static __attribute__((noinline)) void advance_world_now(gripper_t *g, uint64_t now_us)
{
    wsg_sim_world_advance(&g->world, now_us);
}

static void advance_world(void *ctx, uint64_t now_us)
{
    gripper_t *g = ctx;
    if (!wsg_sim_world_current(&g->world, now_us)) {
        advance_world_now(g, now_us);
    }
}

/* The same hook with a physics scene: its own, so that the built-in
 * world's (every request's) tests nothing more. The scene is brought up
 * to every input here; a tick needs nothing else for it. */
static void advance_worlds(void *ctx, uint64_t now_us)
{
    gripper_t *g = ctx;
    advance_world(g, now_us);
    physics_world_advance(g->physics, now_us);
}

/* Both worlds up to now_us (a script's turn, a run). */
static void advance_all(gripper_t *g, uint64_t now_us)
{
    wsg_sim_world_advance(&g->world, now_us);
    if (g->physics != NULL) {
        physics_world_advance(g->physics, now_us);
    }
}

/* --physics: the scene's world, its axis the device's (NULL when built-in). */
static bool open_physics(gripper_t *g)
{
    g->physics = NULL;
    if (g->opts->physics == HOST_PHYSICS_BUILTIN) {
        return true;
    }
    char why[1024];
    float stroke = g->config.stroke_mm;
    float emergency_accel = 2.0f * g->config.accel_max_mm_s2;
    g->physics =
        g->opts->physics == HOST_PHYSICS_SOCKET
            ? plant_socket_world_open(g->opts->plant_socket, g->opts->plant_timeout_ms, stroke,
                                      emergency_accel, hal_clock_now_us(), why, sizeof(why))
            : physics_setup_open(g->opts->scene, stroke, emergency_accel, hal_clock_now_us(), why,
                                 sizeof(why));
    if (g->physics == NULL) {
        host_logf(HAL_LOG_ERROR, "device %u: physics scene: %s", g->index, why);
        return false;
    }
    if (g->opts->part_given) {
        host_logf(HAL_LOG_WARN, "--part is ignored in a physics scene (the scene holds the parts)");
    }
    return true;
}

/* Device index of a fleet: serial + index, tag "<tag>-<index>" (cut to fit). */
static void set_identity(wsg_config_t *cfg, unsigned index)
{
    if (index == 0) {
        return;
    }
    cfg->serial += index;
    char suffix[16];
    int len = snprintf(suffix, sizeof(suffix), "-%u", index);
    size_t keep = sizeof(cfg->tag) - 1u - (size_t)len;
    size_t tag_len = strnlen(cfg->tag, keep);
    memcpy(&cfg->tag[tag_len], suffix, (size_t)len + 1u);
}

/* The gripper's own copy of its options from now on; false when out of
 * memory (it keeps the shared ones). */
static bool own_options(gripper_t *g)
{
    if (g->own_opts == NULL) {
        g->own_opts = malloc(sizeof(*g->own_opts));
        if (g->own_opts == NULL) {
            host_logf(HAL_LOG_ERROR, "device %u: out of memory", g->index);
            return false;
        }
        *g->own_opts = *g->opts;
        g->opts = g->own_opts;
    }
    return true;
}

/* The startup script (--script), at power-on and after a reset. */
static void start_script(gripper_t *g)
{
    if (g->script != NULL) {
        script_power_on(g->script, hal_clock_now_us());
    }
    if (g->script == NULL || g->opts->script == NULL || !g->opts->script_autostart) {
        return;
    }
    /* a file gone since (or one the saved settings chose) fails as a
     * script does: the device starts whatever its store holds */
    script_run_startup(g->script, g->opts->script);
}

bool gripper_init(gripper_t *g, host_loop_t *loop, const host_options_t *opts, unsigned index,
                  gripper_touched_t *touched, struct script_guard *guard)
{
    g->index = index;
    g->opts = opts;
    g->own_opts = NULL;
    const char *model = config_file_device_model(opts->config, index, opts->model);
    const char *script = config_file_device_script(opts->config, index, opts->script);
    const char *fingers = config_file_device_fingers(opts->config, index, opts->fingers);
    bool differs = model != opts->model || script != opts->script || fingers != opts->fingers;
    bool opts_ok = !differs || own_options(g);
    if (g->own_opts != NULL) { /* its [device.N] section */
        g->own_opts->model = model;
        g->own_opts->script = script;
        g->own_opts->fingers = fingers;
    }
    g->touched_list = touched;
    g->ticked_flags = 0u; /* its first tick is due at once (power-on) */
    g->shown_flags = GRIPPER_FLAGS_UNSHOWN;
    g->script = NULL;
    g->script_guard = guard;
    g->step_hook = NULL; /* an observer may set it as the fleet starts the device */
    g->startup_set = NULL;
    g->timing_set = NULL;
    g->startup_cleared = false;
    /* one SocketCAN bus per interface: device 0's */
    bool bus_ok = finger_bus_host_start(&g->fingers, loop, index == 0 ? opts->can_iface : NULL,
                                        g->opts->fingers);
    wsg_sim_model_config(wsg_sim_model_find(g->opts->model), &g->config);
    config_file_apply(opts->config, &g->config);
    set_identity(&g->config, index);
    config_file_apply_device(opts->config, index, &g->config);
    g->config.disconnect_raises_faststop = opts->disconnect_faststop;
    g->config.bin_crc_unchecked = !opts->binary_crc;
    g->config.timing = opts->timing_figures;
    g->config.timing.seed = run_seed_stream(opts->seed, RUN_SEED_TIMING, (uint64_t)index);
    bool physics_ok = open_physics(g);
    power_on_world(g);
    wsg_hal_t hal;
    wsg_sim_world_hal(&g->world, &hal);
    if (g->physics != NULL) {
        physics_world_hal_axis(g->physics, &hal.axis);
        can_loopback_t *loopback = finger_bus_host_loopback(&g->fingers);
        if (loopback != NULL) {
            can_loopback_set_contact(loopback, physics_world_finger_contact(g->physics));
        }
    }
    const hal_can_t *bus = finger_bus_host_can(&g->fingers);
    hal.can = bus != NULL ? *bus : (hal_can_t){NULL, NULL};
    wsg_device_init(&g->device, &g->config, &hal);
    wsg_conn_set_drivers(&g->device, host_drivers, sizeof(host_drivers) / sizeof(host_drivers[0]));
    wsg_runner_init(&g->runner, &g->device, g->physics != NULL ? advance_worlds : advance_world, g);
    if (script_options_enabled(g->opts)) {
        char store[4096];
        bool has_store = script_options_store(g->opts, store, sizeof(store));
        g->script = script_create(&g->device, guard, index, (unsigned)opts->devices,
                                  has_store ? store : NULL);
    }
    return bus_ok && opts_ok && physics_ok;
}

void gripper_start(gripper_t *g)
{
    start_script(g);
}

bool gripper_inject_finger_fault(gripper_t *g, unsigned slot, finger_fault_t fault, bool active)
{
    const hal_can_t *can = finger_bus_host_can(&g->fingers);
    if (slot >= FBUS_SLOTS || can == NULL) {
        return false;
    }
    if (!can->ops->on_demand) {
        return finger_bus_host_inject(&g->fingers, slot, fault, active);
    }
    /* The in-process bus runs only when the device steps: bring it up to
     * this instant first (what the finger sent until now), then let the
     * device see the injection and watch it take effect. */
    gripper_step_now(g);
    bool sent = finger_bus_host_inject(&g->fingers, slot, fault, active);
    gripper_step_now(g);
    return sent;
}

void gripper_release(gripper_t *g)
{
    script_destroy(g->script);
    g->script = NULL;
    finger_bus_host_stop(&g->fingers);
    physics_setup_close(g->physics);
    g->physics = NULL;
    free(g->own_opts);
    g->own_opts = NULL;
    g->opts = NULL;
    free(g->startup_set);
    g->startup_set = NULL;
    free(g->timing_set);
    g->timing_set = NULL;
}

bool gripper_set_startup(gripper_t *g, const char *file, char *why, size_t cap)
{
    if (file == NULL) {
        if (!own_options(g)) {
            snprintf(why, cap, "out of memory");
            return false;
        }
        g->own_opts->script_autostart = false; /* the file stays selected and runs no more */
        g->startup_cleared = true;
        return true;
    }
    const char *store = g->script != NULL ? script_store_dir(g->script) : "";
    const char *name = strncmp(file, "/user/", 6) == 0 ? file + 6 : NULL;
    char path[PATH_MAX];
    struct stat st;
    if (store[0] == '\0') {
        snprintf(why, cap, "there is no /user/ store (--script-dir)");
        return false;
    }
    if (name == NULL || !script_store_name_ok(name) ||
        snprintf(path, sizeof(path), "%s/%s", store, name) >= (int)sizeof(path) ||
        stat(path, &st) != 0 || !S_ISREG(st.st_mode)) {
        snprintf(why, cap, "%s: no such file in the /user/ store", file);
        return false;
    }
    char *copy = strdup(file);
    if (copy == NULL || !own_options(g)) {
        free(copy);
        snprintf(why, cap, "out of memory");
        return false;
    }
    free(g->startup_set);
    g->startup_set = copy;
    g->startup_cleared = false;
    g->own_opts->script = copy;
    g->own_opts->script_autostart = true;
    return true;
}

const char *gripper_startup_choice(const gripper_t *g)
{
    return g->startup_cleared ? "" : g->startup_set;
}

bool gripper_run_script(gripper_t *g, const char *file, char *why, size_t cap)
{
    if (g->script == NULL) { /* no script options: no store, named as the fleet's others */
        g->script =
            script_create(&g->device, g->script_guard, g->index, (unsigned)g->opts->devices, NULL);
        if (g->script == NULL) {
            snprintf(why, cap, "out of memory");
            return false;
        }
    }
    advance_all(g, hal_clock_now_us());
    bool ok = script_run(g->script, file, why, cap);
    wsg_runner_input_done(&g->runner);
    gripper_touch(g);
    return ok;
}

bool gripper_continue_script(gripper_t *g)
{
    if (g->script == NULL || !script_preempted(g->script)) {
        return false;
    }
    if (!script_take_turn(g->script)) {
        return true; /* the pass's budget is spent: a later pass */
    }
    advance_all(g, hal_clock_now_us());
    script_continue(g->script);
    wsg_runner_input_done(&g->runner);
    gripper_touch(g);
    return script_preempted(g->script);
}

uint64_t gripper_tick(gripper_t *g)
{
    /* the world first, due or not (a touch may come from it); the poll
     * then leaves it alone: once is enough, and a direct call is cheaper
     * than the runner's hook (a lone run polls once per simulated ms) */
    advance_all(g, hal_clock_now_us());
    return gripper_tick_advanced(g);
}

bool gripper_may_coast(const gripper_t *g, wsg_coast_t *coast)
{
    return g->script == NULL && wsg_device_coast(&g->device, coast);
}

bool gripper_coasts_at(gripper_t *g, const wsg_coast_t *coast, uint64_t at_us)
{
    wsg_sim_world_advance(&g->world, at_us);
    if (g->physics != NULL) {
        physics_world_advance(g->physics, at_us);
        hal_axis_status_t status;
        physics_world_axis_status(g->physics, &status);
        return wsg_coast_within(coast, &status, wsg_sim_thermal_board_c(&g->world.thermal));
    }
    return wsg_sim_world_coasts(&g->world, coast);
}

unsigned gripper_cruise(gripper_t *g, const wsg_coast_t *coast, uint64_t at_us, unsigned max,
                        bool *outside)
{
    *outside = false;
    if (g->physics != NULL || at_us != g->world.last_us + coast->step_us) {
        return 0u;
    }
    return wsg_sim_world_cruise(&g->world, coast->step_us, max, coast, outside);
}

void gripper_coasted(gripper_t *g, const wsg_coast_t *coast, uint64_t last_us)
{
    wsg_device_coasted(&g->device, last_us);
    g->runner.next_deadline_us = wsg_coast_next_us(coast, last_us); /* as the step would have */
}

uint64_t gripper_tick_advanced(gripper_t *g)
{
    uint64_t next = wsg_runner_poll_advanced(&g->runner);
    g->ticked_flags = wsg_device_flags(&g->device);
    if (g->step_hook != NULL) {
        g->step_hook->stepped(g->step_hook->ctx, g->index, &g->device);
    }
    if (g->script == NULL) {
        return next;
    }
    /* what the script does is input like a client's: due from the next instant */
    uint64_t wake = script_service(g->script);
    wsg_runner_input_done(&g->runner);
    g->ticked_flags = wsg_device_flags(&g->device); /* as the script left them */
    next = g->runner.next_deadline_us;
    return wake < next ? wake : next;
}

void gripper_step_now(gripper_t *g)
{
    (void)wsg_runner_step_now(&g->runner);
}

void gripper_reset(gripper_t *g)
{
    wsg_conn_t *c;
    while ((c = wsg_device_conn_first(&g->device)) != NULL) {
        wsg_conn_close(c, WSG_CLOSE_EXPIRED); /* one without a port behind it */
    }
    if (g->script != NULL) {
        script_forget(g->script);
    }
    power_on_world(g);
    wsg_device_reset(&g->device, &g->config);
    start_script(g);
}

/* Whether a tick of g now, after input on c that its runner's poll need not
 * follow, would still do something: advance the world, serve a script,
 * show its observers (coverage) a flag register they have not seen, or
 * learn a deadline of what is interposed on c's output (the control
 * channel's DELAY holds replies until a time of its own). */
static bool tick_needed(const gripper_t *g, const wsg_conn_t *c)
{
    const wsg_conn_io_t *io = NULL;
    void *io_ctx = NULL;
    wsg_conn_get_io(c, &io, &io_ctx);
    return g->script != NULL || !wsg_sim_world_current(&g->world, hal_clock_now_us()) ||
           wsg_device_flags(&g->device) != g->ticked_flags || io == NULL || io->held != NULL;
}

size_t gripper_feed(gripper_t *g, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                    int end_of_datagram)
{
    /* the touch ticks g at this instant, before the clock moves on; input
     * that left nothing for that tick to do (a query) needs none */
    if (wsg_runner_feed_before_poll(&g->runner, c, bytes, len, end_of_datagram != 0) ||
        tick_needed(g, c)) {
        gripper_touch(g);
    }
    return g->runner.taken;
}

void gripper_input_done(gripper_t *g)
{
    wsg_runner_input_done(&g->runner);
    gripper_touch(g);
}

void gripper_touch(gripper_t *g)
{
    if (!g->touched) {
        g->touched = true;
        list_push_front(&g->touched_list->grippers, &g->touched_link);
    }
}

gripper_t *gripper_take_touched(gripper_touched_t *touched)
{
    list_node_t *node = list_pop_front(&touched->grippers);
    if (node == NULL) {
        return NULL;
    }
    gripper_t *g = LIST_ITEM(node, gripper_t, touched_link);
    g->touched = false;
    return g;
}

bool gripper_set_timing(gripper_t *g, const char *spec, const wsg_timing_t *timing)
{
    char *copy = strdup(spec);
    if (copy == NULL) {
        return false;
    }
    free(g->timing_set);
    g->timing_set = copy;
    g->config.timing = *timing; /* a reset keeps it */
    wsg_device_set_timing(&g->device, timing);
    return true;
}

const char *gripper_timing_name(const gripper_t *g)
{
    return g->timing_set != NULL ? g->timing_set : g->opts->timing;
}
