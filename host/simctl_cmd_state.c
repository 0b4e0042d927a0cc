/* STATE, SESSIONS, RESET, COVERAGE, COVERAGE_RESET, LOG, HELP, BYE. */
#include <cjson/cJSON.h>
#include <stdlib.h>

#include "coverage.h"
#include "gripper.h"
#include "log.h"
#include "simctl_cmd_internal.h"
#include "simctl_delay.h"
#include "simctl_faults.h"
#include "simctl_hooks.h"
#include "simctl_run.h"
#include "state_json.h"
#include "tcp_server.h"
#include "udp_server.h"

wsg_status_t sc_state(simctl_ctx_t *ctx)
{
    sc_reply_owned(ctx, state_json(false));
    return E_SUCCESS;
}

wsg_status_t sc_sessions(simctl_ctx_t *ctx)
{
    cJSON *list = state_json_session_list();
    sc_reply_json(ctx, list);
    return E_SUCCESS;
}

/* A power cycle: connections drop (unobserved: they are not the clients'
 * doing), injected faults go, and the device starts as configured. */
wsg_status_t sc_reset(simctl_ctx_t *ctx)
{
    (void)ctx;
    gripper_t *g = gripper_served();
    simctl_hooks_detach(&g->device);
    simctl_delay_clear_all(false);
    tcp_server_close_all();
    udp_server_close_all();
    simctl_fault_clear_all();
    gripper_reset(g);
    simctl_hooks_attach(&g->device, &g->opts);
    simctl_reset_max_lag();
    host_logf(HAL_LOG_INFO, "device reset to power-on defaults");
    return E_SUCCESS;
}

wsg_status_t sc_coverage(simctl_ctx_t *ctx)
{
    sc_reply_owned(ctx, coverage_report_json(simctl_hooks_strict(), false));
    return E_SUCCESS;
}

wsg_status_t sc_coverage_reset(simctl_ctx_t *ctx)
{
    (void)ctx;
    coverage_reset();
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

wsg_status_t sc_help(simctl_ctx_t *ctx)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned i = 0; i < simctl_table_count(); i++) {
        cJSON_AddItemToArray(list, cJSON_CreateString(simctl_table_at(i)->usage));
    }
    sc_reply_json(ctx, list);
    return E_SUCCESS;
}

wsg_status_t sc_bye(simctl_ctx_t *ctx)
{
    ctx->close = true;
    return E_SUCCESS;
}
