/* SPDX-License-Identifier: BSD-3-Clause */
/* PAUSE, RESUME, STEP, RUN_UNTIL_DONE, SCALE, SIMTIME: the one simulated clock. */
#include <string.h>

#include "clock.h"
#include "commands.h"
#include "commands_internal.h"
#include "gripper.h"
#include "hal_clock.h"
#include "log.h"
#include "scheduler.h"
#include "simctl_ops.h"
#include "wsg/wsg_textbuf.h"
#include "wsg/wsg_timing.h"

#define STEP_MAX_MS 3600000.0 /* one hour of simulated time per STEP */

/* A refused operation's ERR line. */
static wsg_status_t refused(simctl_ctx_t *ctx, const simctl_op_t *op)
{
    return sc_fail(ctx, op->status, "%s", op->why);
}

wsg_status_t sc_pause(simctl_ctx_t *ctx)
{
    simctl_op_t op;
    return simctl_op_pause(ctx->ctl, &op) ? E_SUCCESS : refused(ctx, &op);
}

wsg_status_t sc_resume(simctl_ctx_t *ctx)
{
    simctl_op_t op;
    return simctl_op_resume(ctx->ctl, &op) ? E_SUCCESS : refused(ctx, &op);
}

wsg_status_t sc_step(simctl_ctx_t *ctx)
{
    double ms = 0.0;
    simctl_op_t op;
    if (!sc_number(ctx, 0, &ms)) {
        return E_INVALID_PARAMETER;
    }
    if (!simctl_op_step(ctx->ctl, ms, sc_checking(ctx), &op)) {
        return refused(ctx, &op);
    }
    ctx->deferred = !sc_checking(ctx);
    return E_SUCCESS;
}

/* The long command that runs when RUN_UNTIL_DONE starts has ended (its final
 * reply went out), or another replaced it (which ended it as well). */
static bool operation_ended(void *ctx)
{
    simctl_run_watch_t *run = ctx;
    uint64_t started_us = 0;
    wsg_motion_kind_t motion = wsg_device_motion(run->device, &started_us);
    if (run->queue) {
        run->ended = wsg_device_requests_waiting(run->device) == 0u && motion == WSG_MOTION_NONE;
    } else {
        run->ended = motion != run->motion || started_us != run->started_us;
    }
    return run->ended;
}

/* The simulated time now in ms with three decimals, written backwards into
 * out[0..size); returns where it starts. The clock counts whole µs, so no
 * float formatting: a driver's test suite gets one of these per command,
 * and printf's float path was most of what a reply cost. */
static const char *ms_now(char *out, size_t size)
{
    uint64_t us = hal_clock_now_us();
    char *p = out + size;
    *--p = '\0';
    for (int i = 0; i < 3; i++, us /= 10u) {
        *--p = (char)('0' + us % 10u);
    }
    *--p = '.';
    do {
        *--p = (char)('0' + us % 10u);
        us /= 10u;
    } while (us > 0u);
    return p;
}

#define MS_TEXT_MAX 22u /* a µs count's 17 digits of ms, the point, 3 decimals, the NUL */
#define REPLY_MAX 64u   /* the longest: RUN_UNTIL_DONE=[ms,"limit"] */

/* STEP=ms, or RUN_UNTIL_DONE=[ms,"why"] (why not NULL); on the heap (the
 * caller frees it) */
static char *clock_reply(const char *head, const char *why)
{
    char ms[MS_TEXT_MAX];
    char storage[REPLY_MAX];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, head);
    wsg_textbuf_put_str(&tb, ms_now(ms, sizeof(ms)));
    if (why != NULL) {
        wsg_textbuf_put_str(&tb, ",");
        wsg_textbuf_put_quoted(&tb, why);
        wsg_textbuf_put_str(&tb, "]");
    }
    return strdup(storage);
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
    if (!simclock_paused(simctl_clock(ctx->ctl))) {
        return sc_fail(ctx, E_ACCESS_DENIED, "the clock is running; PAUSE() first");
    }
    const wsg_snapshot_t *snap = wsg_device_snapshot(&ctx->gripper->device);
    bool queue = wsg_device_requests_waiting(&ctx->gripper->device) > 0u;
    if (snap->motion == WSG_MOTION_NONE && !queue) {
        ctx->reply =
            clock_reply("RUN_UNTIL_DONE=[", "idle"); /* nothing that could end: time stays */
        return E_SUCCESS;
    }
    simctl_run_watch_t *run = simctl_run_watch(ctx->ctl);
    *run = (simctl_run_watch_t){
        true, false, &ctx->gripper->device, snap->motion, snap->motion_started_us, queue};
    simctl_step_until_begin(simctl_scheduler(ctx->ctl), (uint64_t)(ms * 1000.0 + 0.5),
                            operation_ended, run);
    ctx->deferred = true;
    return E_SUCCESS;
}

char *simctl_step_reply(simctl_t *ctl)
{
    simctl_run_watch_t *run = simctl_run_watch(ctl);
    if (run->active) {
        run->active = false;
        return clock_reply("RUN_UNTIL_DONE=[", run->ended ? "done" : "limit");
    }
    return clock_reply("STEP=", NULL);
}

wsg_status_t sc_scale(simctl_ctx_t *ctx)
{
    if (ctx->cmd->form == GCL_FORM_SET) {
        double scale = 0.0;
        simctl_op_t op;
        if (!sc_number(ctx, 0, &scale)) {
            return E_INVALID_PARAMETER;
        }
        if (!simctl_op_scale(ctx->ctl, scale, sc_checking(ctx), &op)) {
            return refused(ctx, &op);
        }
        if (sc_checking(ctx)) {
            return E_SUCCESS;
        }
    }
    sc_reply(ctx, "%g", simclock_scale(simctl_clock(ctx->ctl)));
    return E_SUCCESS;
}

/* SIMTIME=[simulated ms, lag ms] */
wsg_status_t sc_simtime(simctl_ctx_t *ctx)
{
    sc_reply(ctx, "[%.3f,%.3f]", (double)hal_clock_now_us() / 1000.0,
             (double)simctl_lag_us(simctl_scheduler(ctx->ctl)) / 1000.0);
    return E_SUCCESS;
}
