/* SPDX-License-Identifier: BSD-3-Clause */
#include "gripper.h"

#include <stdio.h>
#include <string.h>

#include "config_file.h"
#include "finger_bus_host.h"
#include "hal_clock.h"
#include "log.h"
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
        axis->x_mm = axis->stroke_mm;
        axis->target_mm = axis->x_mm;
    }
    wsg_sim_axis_place_part(axis, opts->part_width_mm, opts->part_stiffness_n_mm);
}

static void power_on_world(gripper_t *g)
{
    wsg_sim_world_init(&g->world, &g->config, hal_clock_now_us());
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

void gripper_init(gripper_t *g, const host_options_t *opts, unsigned index)
{
    g->opts = *opts;
    g->opts.model = config_file_device_model(index, opts->model);
    g->index = index;
    wsg_sim_model_config(wsg_sim_model_find(g->opts.model), &g->config);
    config_file_apply(&g->config);
    set_identity(&g->config, index);
    config_file_apply_device(index, &g->config);
    g->config.disconnect_raises_faststop = opts->disconnect_faststop;
    g->config.bin_crc_unchecked = !opts->binary_crc;
    power_on_world(g);
    wsg_hal_t hal;
    wsg_sim_world_hal(&g->world, &hal);
    hal.can = index == 0 ? finger_bus_host_can() : NULL;
    wsg_device_init(&g->device, &g->config, &hal);
    wsg_conn_set_drivers(&g->device, host_drivers, sizeof(host_drivers) / sizeof(host_drivers[0]));
    wsg_runner_init(&g->runner, &g->device, advance_world, g);
    if (index == 0) {
        simctl_observers_attach(&g->device, opts);
    } else if (web_lines_enabled()) {
        wsg_conn_observe(&g->device, web_lines_observer(), NULL); /* the hub is device 0's */
    }
}

uint64_t gripper_tick(gripper_t *g)
{
    wsg_sim_world_advance(&g->world, hal_clock_now_us()); /* a touch may come from the world */
    return wsg_runner_poll(&g->runner);
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
    power_on_world(g);
    wsg_device_reset(&g->device, &g->config);
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

gripper_t *gripper_take_touched(void)
{
    gripper_t *g = touched_first;
    if (g != NULL) {
        touched_first = g->next_touched;
        g->touched = false;
    }
    return g;
}
