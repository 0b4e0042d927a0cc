/* SPDX-License-Identifier: BSD-3-Clause */
/* STATE, SESSIONS, RESET, DEVICE, DEVICES, COVERAGE, COVERAGE_RESET, DRIVER, LOG, BYE
 * (HELP is the command table's, commands.c). */
#include <cjson/cJSON.h>
#include <stdlib.h>

#include "clock.h"
#include "commands_internal.h"
#include "coverage.h"
#include "delay.h"
#include "faults.h"
#include "fleet.h"
#include "log.h"
#include "scheduler.h"
#include "script_json.h"
#include "state_json.h"

wsg_status_t sc_state(simctl_ctx_t *ctx)
{
    cJSON *faults = sc_faults_json(ctx->ctl, ctx->gripper);
    cJSON *script = script_json(ctx->gripper);
    char *faults_text = cJSON_PrintUnformatted(faults);
    char *script_text = cJSON_PrintUnformatted(script);
    state_json_sim_t sim = {.lag_us = simctl_lag_us(simctl_scheduler(ctx->ctl)),
                            .max_lag_us = simctl_max_lag_us(simctl_scheduler(ctx->ctl)),
                            .paused = simclock_paused(simctl_clock(ctx->ctl)),
                            .scale = simclock_scale(simctl_clock(ctx->ctl)),
                            .faults = faults_text,
                            .script = script_text};
    sc_reply_owned(ctx, state_json(ctx->gripper, &sim));
    cJSON_free(faults_text);
    cJSON_free(script_text);
    cJSON_Delete(faults);
    cJSON_Delete(script);
    return E_SUCCESS;
}

wsg_status_t sc_sessions(simctl_ctx_t *ctx)
{
    sc_reply_owned(ctx, state_json_sessions(ctx->gripper));
    return E_SUCCESS;
}

/* A power cycle: connections drop (unobserved: they are not the clients'
 * doing), the device's injected faults go, and it starts as configured. */
wsg_status_t sc_reset(simctl_ctx_t *ctx)
{
    gripper_t *g = ctx->gripper;
    wsg_device_observers_t observers;
    driver_report_power_cycle(coverage_driver(simctl_coverage(ctx->ctl)), g->index);
    wsg_device_take_observers(&g->device, &observers); /* whoever observes */
    simctl_delay_clear_all(simctl_delays(ctx->ctl), &g->device, false);
    fleet_close_connections(simctl_fleet(ctx->ctl), g->index);
    simctl_fault_clear_all(simctl_faults(ctx->ctl), g);
    gripper_reset(g);
    wsg_device_give_observers(&g->device, &observers);
    simctl_reset_max_lag(simctl_scheduler(ctx->ctl));
    host_logf(HAL_LOG_INFO, "device %u reset to power-on defaults", g->index);
    return E_SUCCESS;
}

/* DEVICE=index selects the device the channel's next commands address. */
wsg_status_t sc_device(simctl_ctx_t *ctx)
{
    if (ctx->cmd->form == GCL_FORM_SET) {
        int64_t index = 0;
        if (!sc_integer(ctx, 0, "the device index", 0,
                        (int64_t)fleet_count(simctl_fleet(ctx->ctl)) - 1, &index)) {
            return ctx->failed;
        }
        if (ctx->selected == NULL) {
            return sc_fail(ctx, E_ACCESS_DENIED, "only a control connection selects a device");
        }
        *ctx->selected = (unsigned)index;
        ctx->gripper = fleet_gripper(simctl_fleet(ctx->ctl), (unsigned)index);
    }
    sc_reply(ctx, "%u", ctx->gripper->index);
    return E_SUCCESS;
}

/* DEVICES? [{"index":..,"tcp":..,"udp":..,"serial":..,"tag":..,"model":..}, ...] */
wsg_status_t sc_devices(simctl_ctx_t *ctx)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; i < fleet_count(simctl_fleet(ctx->ctl)); i++) {
        const wsg_config_t *cfg =
            wsg_device_snapshot(&fleet_gripper(simctl_fleet(ctx->ctl), i)->device)->config;
        cJSON *j = cJSON_CreateObject();
        cJSON_AddNumberToObject(j, "index", i);
        cJSON_AddNumberToObject(j, "tcp", fleet_tcp_port(simctl_fleet(ctx->ctl), i));
        cJSON_AddNumberToObject(j, "udp", fleet_udp_port(simctl_fleet(ctx->ctl), i));
        cJSON_AddNumberToObject(j, "serial", cfg->serial);
        cJSON_AddStringToObject(j, "tag", cfg->tag);
        cJSON_AddStringToObject(j, "model", cfg->devtype);
        cJSON_AddItemToArray(list, j);
    }
    sc_reply_json(ctx, list);
    return E_SUCCESS;
}

wsg_status_t sc_coverage(simctl_ctx_t *ctx)
{
    coverage_t *coverage = simctl_coverage(ctx->ctl);
    if (coverage == NULL) {
        return sc_fail(ctx, E_NOT_AVAILABLE, "no coverage is counted");
    }
    sc_reply_owned(ctx, coverage_report_json(coverage, false));
    return E_SUCCESS;
}

/* The report on the driver under test: every live session and the last
 * ended ones, counted with the coverage (docs/testing-your-driver.md). */
wsg_status_t sc_driver(simctl_ctx_t *ctx)
{
    driver_report_t *driver = coverage_driver(simctl_coverage(ctx->ctl));
    if (driver == NULL) {
        return sc_fail(ctx, E_NOT_AVAILABLE, "the driver report is counted with --coverage FILE");
    }
    sc_reply_json(ctx, driver_report_json(driver));
    return E_SUCCESS;
}

wsg_status_t sc_coverage_reset(simctl_ctx_t *ctx)
{
    if (simctl_coverage(ctx->ctl) != NULL) {
        coverage_reset(simctl_coverage(ctx->ctl));
        fleet_show_flags_again(simctl_fleet(ctx->ctl)); /* sampled at each device's next step */
    }
    return E_SUCCESS;
}

wsg_status_t sc_log(simctl_ctx_t *ctx)
{
    const char *text = NULL;
    if (!sc_text(ctx, 0, &text)) {
        return ctx->failed;
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    host_logf(HAL_LOG_INFO, "control: %s", text);
    return E_SUCCESS;
}

wsg_status_t sc_bye(simctl_ctx_t *ctx)
{
    ctx->close = true;
    return E_SUCCESS;
}
