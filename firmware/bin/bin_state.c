/* SPDX-License-Identifier: BSD-3-Clause */
/* State queries 0x40-0x46 and their automatic updates (spec §6): periodic
 * or change-sensitive, several per connection, driven by one timer in the
 * device's queue, due at the earliest subscription. */
#include <math.h>

#include "bin/bin_internal.h"

#define BIN_MIN_PERIOD_US 5000u

static const uint8_t sub_ids[BIN_SUB_COUNT] = {0x40, 0x41, 0x43, 0x44, 0x45};
/* change thresholds (spec §6); 0: any change */
static const float sub_thresholds[BIN_SUB_COUNT] = {0.0f, 0.0f, 0.01f, 0.05f, 0.05f};

static bool sub_is_number(bin_sub_value_t v)
{
    return v >= BIN_SUB_WIDTH;
}

/* The value's current reading: bits for flags and the grip state, a number
 * for the others; encodes the reply values and returns their length. */
static size_t read_value(const wsg_snapshot_t *snap, bin_sub_value_t v, uint8_t *out, float *number,
                         uint32_t *bits)
{
    switch (v) {
    case BIN_SUB_STATE:
        *bits = snap->flags;
        wsg_bin_put_u32(out, *bits);
        return 4;
    case BIN_SUB_GRASP:
        *bits = (uint32_t)snap->grip_state;
        out[0] = (uint8_t)*bits;
        return 1;
    case BIN_SUB_WIDTH:
        *number = snap->position_mm;
        break;
    case BIN_SUB_SPEED:
        *number = snap->speed_mm_s;
        break;
    case BIN_SUB_FORCE:
    case BIN_SUB_COUNT:
        *number = snap->force_n;
        break;
    }
    wsg_bin_put_f32(out, *number);
    return 4;
}

static void send_value(bin_conn_t *b, bin_sub_value_t v, const wsg_snapshot_t *snap,
                       wsg_msg_kind_t kind)
{
    uint8_t values[4];
    bin_sub_t *sub = &b->subs[v];
    size_t len = read_value(snap, v, values, &sub->last_number, &sub->last_bits);
    wsg_bin_send(b, sub_ids[v], E_SUCCESS, values, len, kind);
}

static bool changed(const bin_sub_t *sub, bin_sub_value_t v, const wsg_snapshot_t *snap)
{
    uint8_t scratch[4];
    float number = 0.0f;
    uint32_t bits = 0;
    read_value(snap, v, scratch, &number, &bits);
    if (!sub_is_number(v)) {
        return bits != sub->last_bits;
    }
    return fabsf(number - sub->last_number) >= sub_thresholds[v];
}

static void reschedule(bin_conn_t *b)
{
    wsg_timer_queue_t *q = &b->conn->dev->timers;
    uint64_t due = UINT64_MAX;
    for (unsigned v = 0; v < BIN_SUB_COUNT; v++) {
        if (b->subs[v].on && b->subs[v].next_due_us < due) {
            due = b->subs[v].next_due_us;
        }
    }
    if (due == UINT64_MAX) {
        wsg_timer_cancel(q, &b->timer);
    } else {
        wsg_timer_schedule(q, &b->timer, due);
    }
}

/* Under a timing profile the frames due share the command processor: they
 * wait for their slot when it is busy. */
static bool frames_wait(bin_conn_t *b, wsg_timer_t *timer, uint64_t now_us)
{
    unsigned due = 0;
    for (unsigned v = 0; v < BIN_SUB_COUNT; v++) {
        due += b->subs[v].on && b->subs[v].next_due_us <= now_us ? 1u : 0u;
    }
    conn_t *c = b->conn;
    return wsg_pace_stream_waits(c->dev, timer, &c->stream_slot, due, c->id, now_us);
}

void wsg_bin_updates_fire(wsg_timer_t *timer, uint64_t now_us)
{
    bin_conn_t *b = (bin_conn_t *)(void *)((char *)timer - offsetof(bin_conn_t, timer));
    if (wsg_conn_timed(b->conn) && frames_wait(b, timer, now_us)) {
        return;
    }
    const wsg_snapshot_t *snap = wsg_device_snapshot(bin_device(b));
    for (unsigned v = 0; v < BIN_SUB_COUNT; v++) {
        bin_sub_t *sub = &b->subs[v];
        if (!sub->on || sub->next_due_us > now_us) {
            continue;
        }
        if (!sub->on_change || changed(sub, (bin_sub_value_t)v, snap)) {
            send_value(b, (bin_sub_value_t)v, snap, WSG_MSG_UPDATE);
        }
        /* keep the phase; a late step skips missed periods */
        uint64_t periods = (now_us - sub->next_due_us) / sub->period_us + 1;
        sub->next_due_us += periods * sub->period_us;
    }
    reschedule(b);
}

void wsg_bin_updates_stop(bin_conn_t *b)
{
    for (unsigned v = 0; v < BIN_SUB_COUNT; v++) {
        b->subs[v].on = false;
    }
    wsg_timer_cancel(&b->conn->dev->timers, &b->timer);
}

bool wsg_bin_updates_any(const bin_conn_t *b)
{
    for (unsigned v = 0; v < BIN_SUB_COUNT; v++) {
        if (b->subs[v].on) {
            return true;
        }
    }
    return false;
}

/* flags (bit 0 on, bit 1 change-sensitive), period ms: answered at once. */
static wsg_status_t query(bin_req_t *req, bin_sub_value_t v)
{
    wsg_status_t status = wsg_bin_expect_len(req, 3);
    if (status != E_SUCCESS) {
        return status;
    }
    bin_conn_t *b = req->bin;
    bin_sub_t *sub = &b->subs[v];
    const wsg_snapshot_t *snap = wsg_device_snapshot(req->dev);
    uint8_t flags = req->payload[0];
    uint32_t period_us = (uint32_t)wsg_bin_get_u16(req->payload + 1) * 1000u;
    sub->on = (flags & 0x01u) != 0;
    sub->on_change = (flags & 0x02u) != 0;
    const wsg_timing_t *timing = &b->conn->dev->cfg.timing;
    uint32_t floor_us = timing->enabled ? timing->update_floor_us : BIN_MIN_PERIOD_US;
    sub->period_us = period_us < floor_us ? floor_us : period_us;
    sub->next_due_us = snap->now_us + sub->period_us;
    send_value(b, v, snap, WSG_MSG_REPLY);
    reschedule(b);
    return BIN_REPLIED;
}

wsg_status_t wsg_bin_get_state(bin_req_t *req)
{
    return query(req, BIN_SUB_STATE);
}

wsg_status_t wsg_bin_get_grasp_state(bin_req_t *req)
{
    return query(req, BIN_SUB_GRASP);
}

wsg_status_t wsg_bin_get_width(bin_req_t *req)
{
    return query(req, BIN_SUB_WIDTH);
}

wsg_status_t wsg_bin_get_speed(bin_req_t *req)
{
    return query(req, BIN_SUB_SPEED);
}

wsg_status_t wsg_bin_get_force(bin_req_t *req)
{
    return query(req, BIN_SUB_FORCE);
}

/* u8: bit 0 resets the counters after reading. */
wsg_status_t wsg_bin_get_stats(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_len(req, 1);
    if (status != E_SUCCESS) {
        return status;
    }
    const uint32_t *stats = wsg_device_snapshot(req->dev)->grip_stats;
    uint8_t v[8];
    wsg_bin_put_u32(v, stats[0]);
    wsg_bin_put_u16(v + 4, (uint16_t)(stats[1] > 0xFFFFu ? 0xFFFFu : stats[1]));
    wsg_bin_put_u16(v + 6, (uint16_t)(stats[2] > 0xFFFFu ? 0xFFFFu : stats[2]));
    if (req->payload[0] & 1u) {
        wsg_op_reset_grip_stats(req->dev);
    }
    return wsg_bin_reply_values(req, v, sizeof(v));
}

/* int16 in 0.1 °C (docs/binary-protocol.md). */
wsg_status_t wsg_bin_get_temp(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    float tenths =
        wsg_bin_clamp(wsg_device_snapshot(req->dev)->temperature_c * 10.0f, -32768.0f, 32767.0f);
    /* rounded half away from zero (no roundf on the boards' C library) */
    int16_t value = (int16_t)(tenths + (tenths < 0.0f ? -0.5f : 0.5f));
    uint8_t v[2];
    wsg_bin_put_u16(v, (uint16_t)value);
    return wsg_bin_reply_values(req, v, sizeof(v));
}
