/* AUTOSEND (manual 3.1.7): per-session periodic values, optionally only on
 * change or beyond a delta, scheduled on the device clock without drift. */
#include "dispatch.h"

#define AUTOSEND_MIN_INTERVAL_MS 10
#define AUTOSEND_MAX_INTERVAL_MS 3600000

static const char *const value_names[AS_COUNT] = {
    [AS_POS] = "POS",           [AS_SPEED] = "SPEED",
    [AS_FORCE] = "FORCE",       [AS_GRIPSTATE] = "GRIPSTATE",
    [AS_SYSFLAGS] = "SYSFLAGS", [AS_TEMP] = "TEMP",
};

bool autosend_value_by_name(const char *name, wsg_autosend_value_t *value)
{
    for (unsigned i = 0; i < AS_COUNT; i++) {
        if (gcl_text_equals(name, value_names[i])) {
            *value = (wsg_autosend_value_t)i;
            return true;
        }
    }
    return false;
}

bool autosend_value_is_numeric(wsg_autosend_value_t value)
{
    return value != AS_GRIPSTATE && value != AS_SYSFLAGS;
}

static float numeric_value(const wsg_device_t *dev, wsg_autosend_value_t value)
{
    switch (value) {
    case AS_POS:
        return dev->axis.position_mm;
    case AS_SPEED:
        return dev->axis.velocity_mm_s < 0.0f ? -dev->axis.velocity_mm_s : dev->axis.velocity_mm_s;
    case AS_FORCE:
        return dev->axis.force_n;
    case AS_TEMP:
        return dev->temperature_c;
    default:
        return 0.0f;
    }
}

static uint32_t state_value(const wsg_device_t *dev, const wsg_session_t *s,
                            wsg_autosend_value_t value)
{
    return value == AS_SYSFLAGS ? flags_for_session(dev, s) : (uint32_t)dev->grip.state;
}

void autosend_put_value(const wsg_device_t *dev, const wsg_session_t *s, wsg_autosend_value_t value,
                        textbuf_t *tb)
{
    if (value == AS_SYSFLAGS) {
        textbuf_put_bits(tb, flags_for_session(dev, s), WSG_SYSFLAG_COUNT);
    } else if (value == AS_GRIPSTATE) {
        textbuf_put_uint(tb, (uint32_t)dev->grip.state);
    } else {
        textbuf_put_float(tb, numeric_value(dev, value));
    }
}

static wsg_status_t read_option(cmd_ctx_t *ctx, wsg_autosend_value_t value, wsg_autosend_sub_t *sub)
{
    if (ctx->cmd->argc < 3) {
        return E_SUCCESS;
    }
    if (!autosend_value_is_numeric(value)) {
        return arg_bool(ctx, 2, &sub->on_change);
    }
    wsg_status_t status = arg_float(ctx, 2, &sub->delta);
    if (status == E_SUCCESS && sub->delta < 0.0f) {
        status = E_RANGE_ERROR;
    }
    sub->use_delta = status == E_SUCCESS;
    return status;
}

wsg_status_t cmd_autosend(cmd_ctx_t *ctx)
{
    const char *name = NULL;
    int32_t interval = 0;
    wsg_autosend_value_t value = AS_POS;
    wsg_status_t status = arg_text(ctx, 0, &name);
    if (status == E_SUCCESS && !autosend_value_by_name(name, &value)) {
        status = E_INVALID_PARAMETER;
    }
    if (status == E_SUCCESS) {
        status = arg_int(ctx, 1, &interval);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    if (interval != 0 &&
        (interval < AUTOSEND_MIN_INTERVAL_MS || interval > AUTOSEND_MAX_INTERVAL_MS)) {
        return E_RANGE_ERROR;
    }
    wsg_autosend_sub_t sub = {0};
    status = read_option(ctx, value, &sub);
    if (status != E_SUCCESS) {
        return status;
    }
    sub.interval_ms = (uint32_t)interval;
    sub.next_due_us = ctx->dev->now_us; /* first value at the next step, after the ACK */
    ctx->session->autosend[value] = sub;
    reply_ack(ctx);
    return E_SUCCESS;
}

static bool should_send(const wsg_device_t *dev, const wsg_session_t *s, wsg_autosend_value_t value,
                        const wsg_autosend_sub_t *sub)
{
    if (!sub->sent_once) {
        return true;
    }
    if (autosend_value_is_numeric(value)) {
        float change = numeric_value(dev, value) - sub->last_number;
        return !sub->use_delta || (change < 0.0f ? -change : change) >= sub->delta;
    }
    return !sub->on_change || state_value(dev, s, value) != sub->last_bits;
}

static void send_value(wsg_device_t *dev, wsg_session_t *s, wsg_autosend_value_t value)
{
    char storage[WSG_REPLY_MAX];
    textbuf_t tb;
    textbuf_init(&tb, storage, sizeof(storage));
    textbuf_put_char(&tb, '@');
    textbuf_put_str(&tb, value_names[value]);
    textbuf_put_char(&tb, '=');
    autosend_put_value(dev, s, value, &tb);
    session_send(dev, s, &tb, WSG_LINE_AUTOSEND);
}

/* Keeps the period's phase: a late step skips the periods it missed. */
static void schedule_next(wsg_autosend_sub_t *sub, uint64_t now_us)
{
    uint64_t period_us = (uint64_t)sub->interval_ms * 1000u;
    sub->next_due_us += period_us;
    if (sub->next_due_us <= now_us) {
        uint64_t behind = (now_us - sub->next_due_us) / period_us + 1u;
        sub->missed += (uint32_t)behind;
        sub->next_due_us += behind * period_us;
    }
}

static void session_step(wsg_device_t *dev, wsg_session_t *s)
{
    for (unsigned v = 0; v < AS_COUNT && s->in_use; v++) {
        wsg_autosend_sub_t *sub = &s->autosend[v];
        if (sub->interval_ms == 0u || dev->now_us < sub->next_due_us) {
            continue;
        }
        wsg_autosend_value_t value = (wsg_autosend_value_t)v;
        if (should_send(dev, s, value, sub)) {
            if (!sub->sent_once) {
                sub->next_due_us = dev->now_us; /* the period runs from the first value */
            }
            sub->sent_once = true;
            sub->last_number = numeric_value(dev, value);
            sub->last_bits = state_value(dev, s, value);
            send_value(dev, s, value);
        }
        schedule_next(sub, dev->now_us);
    }
}

void autosend_step(wsg_device_t *dev)
{
    for (unsigned i = 0; i < WSG_MAX_SESSIONS; i++) {
        if (dev->sessions[i].in_use) {
            session_step(dev, &dev->sessions[i]);
        }
    }
}

uint64_t autosend_next_due_us(const wsg_device_t *dev)
{
    uint64_t next = UINT64_MAX;
    for (unsigned i = 0; i < WSG_MAX_SESSIONS; i++) {
        const wsg_session_t *s = &dev->sessions[i];
        for (unsigned v = 0; v < AS_COUNT && s->in_use; v++) {
            if (s->autosend[v].interval_ms != 0u && s->autosend[v].next_due_us < next) {
                next = s->autosend[v].next_due_us;
            }
        }
    }
    return next;
}
