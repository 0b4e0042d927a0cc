/* SPDX-License-Identifier: BSD-3-Clause */
/* PAUSE, RESUME, STEP, RUN_UNTIL_DONE, SCALE, SIMTIME: the one simulated clock. */
#include <stdio.h>

#include "clock.h"
#include "commands.h"
#include "commands_internal.h"
#include "gripper.h"
#include "hal_clock.h"
#include "log.h"
#include "scheduler.h"

#define STEP_MAX_MS 3600000.0 /* one hour of simulated time per STEP */

/* RUN_UNTIL_DONE: the operation it waits for, and how the run ended. */
typedef struct {
    bool active; /* the running step is a RUN_UNTIL_DONE */
    bool ended;  /* the operation ended before the limit */
    wsg_device_t *device;
    wsg_motion_kind_t motion;
    uint64_t started_us;
} run_watch_t;

static run_watch_t run;

wsg_status_t sc_pause(simctl_ctx_t *ctx)
{
    (void)ctx;
    if (!simclock_paused()) {
        simctl_tick(); /* everything due up to now runs before time stops */
        simclock_pause();
        host_logf(HAL_LOG_INFO, "clock paused");
    }
    return E_SUCCESS;
}

wsg_status_t sc_resume(simctl_ctx_t *ctx)
{
    (void)ctx;
    if (simclock_paused()) {
        simclock_resume();
        host_logf(HAL_LOG_INFO, "clock resumed at %.3fx", simclock_scale());
    }
    return E_SUCCESS;
}

wsg_status_t sc_step(simctl_ctx_t *ctx)
{
    double ms = 0.0;
    if (!sc_number(ctx, 0, &ms)) {
        return E_INVALID_PARAMETER;
    }
    if (!(ms > 0.0 && ms <= STEP_MAX_MS)) {
        return sc_fail(ctx, E_RANGE_ERROR, "ms must be above 0 and at most %.0f", STEP_MAX_MS);
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    if (!simclock_paused()) {
        return sc_fail(ctx, E_ACCESS_DENIED, "the clock is running; PAUSE() first");
    }
    run.active = false; /* its reply is STEP's, even if the last run's never went out */
    simctl_step_begin((uint64_t)(ms * 1000.0 + 0.5));
    ctx->deferred = true;
    return E_SUCCESS;
}

/* The long command that runs when RUN_UNTIL_DONE starts has ended (its final
 * reply went out), or another replaced it (which ended it as well). */
static bool operation_ended(void *ctx)
{
    (void)ctx;
    uint64_t started_us = 0;
    wsg_motion_kind_t motion = wsg_device_motion(run.device, &started_us);
    run.ended = motion != run.motion || started_us != run.started_us;
    return run.ended;
}

static char *run_reply(const char *why)
{
    char *text = NULL;
    if (asprintf(&text, "RUN_UNTIL_DONE=[%.3f,\"%s\"]", (double)hal_clock_now_us() / 1000.0, why) <
        0) {
        return NULL;
    }
    return text;
}

wsg_status_t sc_run_until_done(simctl_ctx_t *ctx)
{
    double ms = 0.0;
    if (!sc_number(ctx, 0, &ms)) {
        return E_INVALID_PARAMETER;
    }
    if (!(ms > 0.0 && ms <= STEP_MAX_MS)) {
        return sc_fail(ctx, E_RANGE_ERROR, "max_ms must be above 0 and at most %.0f", STEP_MAX_MS);
    }
    if (sc_checking(ctx)) {
        return E_SUCCESS;
    }
    if (!simclock_paused()) {
        return sc_fail(ctx, E_ACCESS_DENIED, "the clock is running; PAUSE() first");
    }
    const wsg_snapshot_t *snap = wsg_device_snapshot(&ctx->gripper->device);
    if (snap->motion == WSG_MOTION_NONE) {
        ctx->reply = run_reply("idle"); /* nothing that could end: time stays */
        return E_SUCCESS;
    }
    run = (run_watch_t){true, false, &ctx->gripper->device, snap->motion, snap->motion_started_us};
    simctl_step_until_begin((uint64_t)(ms * 1000.0 + 0.5), operation_ended, NULL);
    ctx->deferred = true;
    return E_SUCCESS;
}

char *simctl_step_reply(void)
{
    if (run.active) {
        run.active = false;
        return run_reply(run.ended ? "done" : "limit");
    }
    char *text = NULL;
    if (asprintf(&text, "STEP=%.3f", (double)hal_clock_now_us() / 1000.0) < 0) {
        return NULL;
    }
    return text;
}

wsg_status_t sc_scale(simctl_ctx_t *ctx)
{
    if (ctx->cmd->form == GCL_FORM_SET) {
        double scale = 0.0;
        if (!sc_number(ctx, 0, &scale)) {
            return E_INVALID_PARAMETER;
        }
        if (!(scale >= SIMCLOCK_SCALE_MIN && scale <= SIMCLOCK_SCALE_MAX)) {
            return sc_fail(ctx, E_RANGE_ERROR, "the scale must be %g to %g", SIMCLOCK_SCALE_MIN,
                           SIMCLOCK_SCALE_MAX);
        }
        if (sc_checking(ctx)) {
            return E_SUCCESS;
        }
        simctl_tick();                   /* the old rate applies up to now */
        (void)simclock_set_scale(scale); /* in range: checked above */
        simctl_reset_max_lag();
        host_logf(HAL_LOG_INFO, "clock scale %.3fx", scale);
    }
    sc_reply(ctx, "%g", simclock_scale());
    return E_SUCCESS;
}

/* SIMTIME=[simulated ms, lag ms] */
wsg_status_t sc_simtime(simctl_ctx_t *ctx)
{
    sc_reply(ctx, "[%.3f,%.3f]", (double)hal_clock_now_us() / 1000.0,
             (double)simctl_lag_us() / 1000.0);
    return E_SUCCESS;
}
