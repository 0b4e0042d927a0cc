/* SPDX-License-Identifier: BSD-3-Clause */
#include "gripper.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "config_file.h"
#include "finger_bus_host.h"
#include "hal_clock.h"
#include "log.h"
#include "script.h"
#include "script_options.h"
#include "sim/observers.h"
#include "sim/sim_models.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_gcl.h"
#include "web/web_lines.h"

/* What a connection opened without a driver (--protocol auto) may speak:
 * the binary protocol claims its preamble byte, GCL everything else. */
static const wsg_proto_driver_t *const host_drivers[] = {&wsg_bin_driver, &wsg_gcl_driver};

/* A part given at start sits between the jaws: open them beyond it. */
static void place_start_part(gripper_t *g)
{
    sim_axis_t *axis = &g->world.axis;
    const host_options_t *opts = &g->opts;
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
    if (g->opts.part_given) {
        place_start_part(g);
    }
    wsg_runner_due_now(&g->runner);
}

static void advance_world(void *ctx, uint64_t now_us)
{
    gripper_t *g = ctx;
    wsg_sim_world_advance(&g->world, now_us);
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

/* The startup script (--script), at power-on and after a reset. */
static void start_script(gripper_t *g)
{
    if (g->script != NULL) {
        script_power_on(g->script, hal_clock_now_us());
    }
    if (g->script == NULL || g->opts.script == NULL || !g->opts.script_autostart) {
        return;
    }
    char why[256];
    if (!script_run(g->script, g->opts.script, why, sizeof(why))) {
        host_logf(HAL_LOG_ERROR, "script: %s", why);
    }
}

void gripper_init(gripper_t *g, const host_options_t *opts, unsigned index)
{
    g->opts = *opts;
    g->opts.model = config_file_device_model(opts->config, index, opts->model);
    g->opts.script = config_file_device_script(opts->config, index, opts->script);
    g->index = index;
    wsg_sim_model_config(wsg_sim_model_find(g->opts.model), &g->config);
    config_file_apply(opts->config, &g->config);
    set_identity(&g->config, index);
    config_file_apply_device(opts->config, index, &g->config);
    g->config.disconnect_raises_faststop = opts->disconnect_faststop;
    g->config.bin_crc_unchecked = !opts->binary_crc;
    power_on_world(g);
    wsg_hal_t hal;
    wsg_sim_world_hal(&g->world, &hal);
    const hal_can_t *bus = index == 0 ? finger_bus_host_can() : NULL;
    hal.can = bus != NULL ? *bus : (hal_can_t){NULL, NULL};
    wsg_device_init(&g->device, &g->config, &hal);
    wsg_conn_set_drivers(&g->device, host_drivers, sizeof(host_drivers) / sizeof(host_drivers[0]));
    wsg_runner_init(&g->runner, &g->device, advance_world, g);
    if (index == 0) {
        simctl_observers_attach(&g->device, opts);
    } else if (opts->web_lines != NULL) {
        /* the hub is device 0's */
        wsg_conn_observe(&g->device, web_lines_observer(), opts->web_lines);
    }
    g->script = NULL;
    g->startup_set = NULL;
    g->startup_cleared = false;
    if (script_options_enabled(&g->opts)) {
        char store[4096];
        bool has_store = script_options_store(&g->opts, store, sizeof(store));
        g->script =
            script_create(&g->device, index, (unsigned)opts->devices, has_store ? store : NULL);
    }
    start_script(g);
}

void gripper_release(gripper_t *g)
{
    script_destroy(g->script);
    g->script = NULL;
    free(g->startup_set);
    g->startup_set = NULL;
}

bool gripper_set_startup(gripper_t *g, const char *file, char *why, size_t cap)
{
    if (file == NULL) {
        g->opts.script_autostart = false; /* the file stays selected and runs no more */
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
    if (copy == NULL) {
        snprintf(why, cap, "out of memory");
        return false;
    }
    free(g->startup_set);
    g->startup_set = copy;
    g->startup_cleared = false;
    g->opts.script = copy;
    g->opts.script_autostart = true;
    return true;
}

const char *gripper_startup_choice(const gripper_t *g)
{
    return g->startup_cleared ? "" : g->startup_set;
}

bool gripper_run_script(gripper_t *g, const char *file, char *why, size_t cap)
{
    if (g->script == NULL) {
        g->script = script_create(&g->device, g->index, 1, NULL);
        if (g->script == NULL) {
            snprintf(why, cap, "out of memory");
            return false;
        }
    }
    wsg_sim_world_advance(&g->world, hal_clock_now_us());
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
    wsg_sim_world_advance(&g->world, hal_clock_now_us());
    script_continue(g->script);
    wsg_runner_input_done(&g->runner);
    gripper_touch(g);
    return script_preempted(g->script);
}

uint64_t gripper_tick(gripper_t *g)
{
    wsg_sim_world_advance(&g->world, hal_clock_now_us()); /* a touch may come from the world */
    uint64_t next = wsg_runner_poll(&g->runner);
    if (g->script == NULL) {
        return next;
    }
    /* what the script does is input like a client's: due from the next instant */
    uint64_t wake = script_service(g->script);
    wsg_runner_input_done(&g->runner);
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

void gripper_feed(gripper_t *g, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                  int end_of_datagram)
{
    wsg_runner_feed(&g->runner, c, bytes, len, end_of_datagram != 0);
    gripper_touch(g);
}

void gripper_input_done(gripper_t *g)
{
    wsg_runner_input_done(&g->runner);
    gripper_touch(g);
}

static gripper_t *touched_first;

void gripper_touch(gripper_t *g)
{
    if (!g->touched) {
        g->touched = true;
        g->next_touched = touched_first;
        touched_first = g;
    }
}

bool gripper_touched_any(void)
{
    return touched_first != NULL;
}

gripper_t *gripper_take_touched(void)
{
    gripper_t *g = touched_first;
    if (g != NULL) {
        touched_first = g->next_touched;
        g->touched = false;
    }
    return g;
}
