/* SPDX-License-Identifier: BSD-3-Clause */
#include "can_harness.h"

#include <stdlib.h>
#include <string.h>

#include "can_loopback.h"

static uint64_t next_due;
static can_loopback_t *bus; /* the loopback bus of the last t_start, NULL: none */

can_loopback_t *t_bus(void)
{
    return bus;
}

bool t_log_contains(const char *text)
{
    for (int level = HAL_LOG_DEBUG; level <= HAL_LOG_ERROR; level++) {
        if (h_log_contains((hal_log_level_t)level, text)) {
            return true;
        }
    }
    return false;
}

static const hal_can_t *start_loopback(const char *fingers)
{
    next_due = 0;
    fbus_type_t types[FBUS_SLOTS];
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    ck_assert(wsg_finger_node_parse_pair(fingers, types));
    can_loopback_destroy(bus);
    bus = can_loopback_create(types, &params);
    ck_assert_ptr_nonnull(bus);
    return can_loopback_bus(bus);
}

void t_start(const char *fingers)
{
    if (fingers == NULL) {
        next_due = 0;
        h_setup_on_can(NULL);
        return;
    }
    h_setup_on_can(start_loopback(fingers));
}

/* The loopback bus behind a controller that drops TARE commands, or whose
 * fingers are held up. */
static const hal_can_t *lossless_bus;
static hal_can_t lossy_bus;
static unsigned tares_to_lose;
static unsigned tares_sent;
static bool fingers_held;

static bool lossy_send(void *ctx, const hal_can_frame_t *frame)
{
    (void)ctx;
    uint8_t command;
    if (wsg_fbus_unpack_command(frame, &command) && command == FBUS_CMD_TARE) {
        tares_sent++;
        if (tares_to_lose > 0u) {
            tares_to_lose--;
            return true; /* on the wire, never taken by the node */
        }
    }
    return hal_can_send(lossless_bus, frame);
}

static bool lossy_recv(void *ctx, hal_can_frame_t *frame)
{
    (void)ctx;
    return !fingers_held && hal_can_recv(lossless_bus, frame); /* it steps the nodes */
}

static bool lossy_set_filters(void *ctx, const hal_can_filter_t *filters, unsigned count)
{
    (void)ctx;
    return hal_can_set_filters(lossless_bus, filters, count);
}

/* [on_demand]: the wrapped bus says what the loopback would */
static const hal_can_ops_t lossy_ops[2] = {
    {lossy_send, lossy_recv, lossy_set_filters, false, NULL, NULL, NULL, NULL},
    {lossy_send, lossy_recv, lossy_set_filters, true, NULL, NULL, NULL, NULL}};

static void start_wrapped(const char *fingers, const hal_can_ops_t *ops, unsigned lost)
{
    lossless_bus = start_loopback(fingers);
    lossy_bus = (hal_can_t){ops, NULL};
    tares_to_lose = lost;
    tares_sent = 0;
    fingers_held = false;
    h_setup_on_can(&lossy_bus);
}

void t_start_losing_tares(const char *fingers, unsigned lost)
{
    start_wrapped(fingers, &lossy_ops[true], lost);
}

void t_start_real_time(const char *fingers)
{
    start_wrapped(fingers, &lossy_ops[false], 0);
}

/* The loopback bus, polls and all, behind a controller that counts them. */
static unsigned polls;
static unsigned skips_told;
static uint64_t skip_told_us;

static const hal_can_frame_t *counting_recv_many(void *ctx, unsigned *count)
{
    (void)ctx;
    polls++;
    hal_can_frame_t one;
    const hal_can_frame_t *frames = hal_can_recv_many(lossless_bus, &one, count);
    ck_assert_ptr_ne(frames, &one); /* the loopback hands its frames out in place */
    return frames;
}

static const uint64_t *counting_quiet_until_us(void *ctx)
{
    (void)ctx;
    return hal_can_quiet_until_us(lossless_bus, NULL);
}

static void counting_polls_skipped(void *ctx, uint64_t last_us)
{
    (void)ctx;
    skips_told++;
    skip_told_us = last_us;
    hal_can_polls_skipped(lossless_bus, last_us);
}

static const hal_can_ops_t counting_ops = {
    lossy_send,         lossy_recv, lossy_set_filters,       true,
    counting_recv_many, NULL,       counting_quiet_until_us, counting_polls_skipped};

void t_start_counting_polls(const char *fingers)
{
    polls = 0;
    skips_told = 0;
    skip_told_us = 0;
    start_wrapped(fingers, &counting_ops, 0);
}

unsigned t_polls(void)
{
    return polls;
}

unsigned t_skips_told(uint64_t *last_us)
{
    *last_us = skip_told_us;
    return skips_told;
}

void t_hold_fingers(bool held)
{
    fingers_held = held;
}

unsigned t_tares_sent(void)
{
    return tares_sent;
}

void t_run_ms(uint32_t ms)
{
    for (uint32_t i = 0; i < ms; i++) {
        h_now_us += 1000u;
        wsg_sim_world_advance(&h_world, h_now_us);
        if (h_now_us >= next_due || i == 0) {
            wsg_device_step(&h_dev);
            next_due = wsg_device_next_deadline_us(&h_dev);
        }
    }
}

const char *t_ask(const char *line)
{
    h_discard(&h_main);
    send_line(&h_main, line);
    while (h_unread(&h_main) > 0) {
        const char *text = h_next_line(&h_main);
        if (h_last_read(&h_main)->kind == WSG_MSG_REPLY) {
            h_discard(&h_main);
            return text;
        }
    }
    return "<no reply>";
}

int t_until(const char *line, const char *reply, uint32_t timeout_ms)
{
    for (uint32_t ms = 0; ms <= timeout_ms; ms++) {
        if (strcmp(t_ask(line), reply) == 0) {
            return (int)ms;
        }
        t_run_ms(1);
    }
    return -1;
}

float t_ask_float(const char *line)
{
    const char *reply = t_ask(line);
    const char *eq = strchr(reply, '=');
    ck_assert_msg(eq != NULL, "%s: %s", line, reply);
    return strtof(eq + 1, NULL);
}
