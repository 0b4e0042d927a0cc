/* SPDX-License-Identifier: BSD-3-Clause */
/* AUTOSEND (manual 3.1.7): per-connection periodic values, optionally only
 * on change or beyond a delta, scheduled on the device clock without drift.
 * One timer per connection, due at its earliest subscription. */
#include <stddef.h>

#include "gcl/gcl_internal.h"

#define AUTOSEND_MIN_INTERVAL_MS 10
#define AUTOSEND_MAX_INTERVAL_MS 3600000

static const char *const value_names[AS_COUNT] = {
    [AS_POS] = "POS",           [AS_SPEED] = "SPEED",
    [AS_FORCE] = "FORCE",       [AS_GRIPSTATE] = "GRIPSTATE",
    [AS_SYSFLAGS] = "SYSFLAGS", [AS_TEMP] = "TEMP",
};

static bool autosend_value_by_name(const char *name, wsg_autosend_value_t *value)
{
    for (unsigned i = 0; i < AS_COUNT; i++) {
        if (wsg_gcl_text_equals(name, value_names[i])) {
            *value = (wsg_autosend_value_t)i;
            return true;
        }
    }
    return false;
}

const char *wsg_gcl_autosend_name(wsg_autosend_value_t value)
{
    return (unsigned)value < AS_COUNT ? value_names[value] : "?";
}

static bool autosend_value_is_numeric(wsg_autosend_value_t value)
{
    return value != AS_GRIPSTATE && value != AS_SYSFLAGS;
}

/* SYSFLAGS as this connection reads it: SF_CMD_FAILURE is its own. */
uint32_t wsg_gcl_flags(const gcl_conn_t *g, const wsg_snapshot_t *snap)
{
    uint32_t own = g->cmd_failed ? WSG_FLAG(SF_CMD_FAILURE) : 0u;
    return (snap->flags & ~WSG_FLAG(SF_CMD_FAILURE)) | own;
}

static float numeric_value(const wsg_snapshot_t *snap, wsg_autosend_value_t value)
{
    switch (value) {
    case AS_POS:
        return snap->position_mm;
    case AS_SPEED:
        return snap->speed_mm_s;
    case AS_FORCE:
        return snap->force_n;
    case AS_TEMP:
        return snap->temperature_c;
    default:
        return 0.0f;
    }
}

static uint32_t state_value(const gcl_conn_t *g, const wsg_snapshot_t *snap,
                            wsg_autosend_value_t value)
{
    return value == AS_SYSFLAGS ? wsg_gcl_flags(g, snap) : (uint32_t)snap->grip_state;
}

static void put_value(const gcl_conn_t *g, const wsg_snapshot_t *snap, wsg_autosend_value_t value,
                      wsg_textbuf_t *tb)
{
    if (value == AS_SYSFLAGS) {
        wsg_textbuf_put_bits(tb, wsg_gcl_flags(g, snap), WSG_SYSFLAG_COUNT);
    } else if (value == AS_GRIPSTATE) {
        wsg_textbuf_put_uint(tb, (uint32_t)snap->grip_state);
    } else {
        wsg_textbuf_put_float(tb, numeric_value(snap, value));
    }
}

static wsg_status_t read_option(cmd_ctx_t *ctx, wsg_autosend_value_t value, gcl_autosend_sub_t *sub)
{
    if (ctx->cmd->argc < 3) {
        return E_SUCCESS;
    }
    if (!autosend_value_is_numeric(value)) {
        return wsg_arg_bool(ctx, 2, &sub->on_change);
    }
    wsg_status_t status = wsg_arg_float(ctx, 2, &sub->delta);
    if (status == E_SUCCESS && sub->delta < 0.0f) {
        status = E_RANGE_ERROR;
    }
    sub->use_delta = status == E_SUCCESS;
    return status;
}

wsg_status_t wsg_cmd_autosend(cmd_ctx_t *ctx)
{
    const char *name = NULL;
    int32_t interval = 0;
    wsg_autosend_value_t value = AS_POS;
    wsg_status_t status = wsg_arg_text(ctx, 0, &name);
    if (status == E_SUCCESS && !autosend_value_by_name(name, &value)) {
        status = E_INVALID_PARAMETER;
    }
    if (status == E_SUCCESS) {
        status = wsg_arg_int(ctx, 1, &interval);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    if (interval != 0 &&
        (interval < AUTOSEND_MIN_INTERVAL_MS || interval > AUTOSEND_MAX_INTERVAL_MS)) {
        return E_RANGE_ERROR;
    }
    gcl_autosend_sub_t sub = {0};
    status = read_option(ctx, value, &sub);
    if (status != E_SUCCESS) {
        return status;
    }
    sub.interval_ms = (uint32_t)interval;
    sub.next_due_us = wsg_device_snapshot(ctx->dev)->now_us; /* the next step, after the ACK */
    ctx->gcl->autosend[value] = sub;
    wsg_reply_ack(ctx);
    wsg_autosend_reschedule(ctx->gcl);
    return E_SUCCESS;
}

static bool should_send(const gcl_conn_t *g, const wsg_snapshot_t *snap, wsg_autosend_value_t value,
                        const gcl_autosend_sub_t *sub)
{
    if (!sub->sent_once) {
        return true;
    }
    if (autosend_value_is_numeric(value)) {
        float change = numeric_value(snap, value) - sub->last_number;
        return !sub->use_delta || (change < 0.0f ? -change : change) >= sub->delta;
    }
    return !sub->on_change || state_value(g, snap, value) != sub->last_bits;
}

static void send_value(gcl_conn_t *g, const wsg_snapshot_t *snap, wsg_autosend_value_t value)
{
    char storage[WSG_REPLY_MAX];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_char(&tb, '@');
    wsg_textbuf_put_str(&tb, value_names[value]);
    wsg_textbuf_put_char(&tb, '=');
    put_value(g, snap, value, &tb);
    wsg_gcl_send(g, &tb, WSG_MSG_UPDATE);
}

/* Keeps the period's phase: a late step skips the periods it missed. */
static void schedule_next(gcl_autosend_sub_t *sub, uint64_t now_us)
{
    uint64_t period_us = (uint64_t)sub->interval_ms * 1000u;
    sub->next_due_us += period_us;
    if (sub->next_due_us <= now_us) {
        uint64_t behind = (now_us - sub->next_due_us) / period_us + 1u;
        sub->missed += (uint32_t)behind;
        sub->next_due_us += behind * period_us;
    }
}

bool wsg_autosend_any(const gcl_conn_t *g)
{
    for (unsigned i = 0; i < AS_COUNT; i++) {
        if (g->autosend[i].interval_ms != 0u) {
            return true;
        }
    }
    return false;
}

/* The connection's timer, due at its earliest subscription (or none). */
void wsg_autosend_reschedule(gcl_conn_t *g)
{
    wsg_timer_queue_t *timers = &g->conn->dev->timers;
    uint64_t next = UINT64_MAX;
    for (unsigned v = 0; v < AS_COUNT; v++) {
        const gcl_autosend_sub_t *sub = &g->autosend[v];
        if (sub->interval_ms != 0u && sub->next_due_us < next) {
            next = sub->next_due_us;
        }
    }
    if (next == UINT64_MAX) {
        wsg_timer_cancel(timers, &g->autosend_timer);
    } else {
        wsg_timer_schedule(timers, &g->autosend_timer, next);
    }
}

/* Under a timing profile the values due share the command processor:
 * they wait for their slot when it is busy. */
static bool values_wait(gcl_conn_t *g, wsg_timer_t *timer, uint64_t now_us)
{
    unsigned due = 0;
    for (unsigned v = 0; v < AS_COUNT; v++) {
        due += g->autosend[v].interval_ms != 0u && g->autosend[v].next_due_us <= now_us ? 1u : 0u;
    }
    conn_t *c = g->conn;
    return wsg_pace_stream_waits(c->dev, timer, &c->stream_slot, due, c->id, now_us);
}

void wsg_autosend_fire(wsg_timer_t *timer, uint64_t now_us)
{
    gcl_conn_t *g = (gcl_conn_t *)(void *)((char *)timer - offsetof(gcl_conn_t, autosend_timer));
    if (wsg_conn_timed(g->conn) && values_wait(g, timer, now_us)) {
        return;
    }
    const wsg_snapshot_t *snap = wsg_device_snapshot(gcl_device(g));
    for (unsigned v = 0; v < AS_COUNT && g->conn->open; v++) {
        gcl_autosend_sub_t *sub = &g->autosend[v];
        if (sub->interval_ms == 0u || now_us < sub->next_due_us) {
            continue;
        }
        wsg_autosend_value_t value = (wsg_autosend_value_t)v;
        if (should_send(g, snap, value, sub)) {
            if (!sub->sent_once) {
                sub->next_due_us = now_us; /* the period runs from the first value */
            }
            sub->sent_once = true;
            sub->last_number = numeric_value(snap, value);
            sub->last_bits = state_value(g, snap, value);
            send_value(g, snap, value);
        }
        schedule_next(sub, now_us);
    }
    if (g->conn->open) {
        wsg_autosend_reschedule(g);
    }
}
