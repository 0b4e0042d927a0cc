/* SPDX-License-Identifier: BSD-3-Clause */
#include "can_harness.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can_loopback.h"
#include "hal_clock.h"
#include "hal_log.h"
#include "sim/sim_models.h"
#include "wsg/wsg_gcl.h"

#define T_START_US 3000000u
#define T_LINE 1100

wsg_device_t t_dev;
sim_world_t t_world;
static uint64_t next_due;
uint64_t t_now_us;
static wsg_conn_t conn;
static char last_line[T_LINE];
static bool have_line;
static char log_text[8192];

uint64_t hal_clock_now_us(void)
{
    return t_now_us;
}

void hal_log(hal_log_level_t level, const char *message)
{
    (void)level;
    size_t used = strlen(log_text);
    snprintf(log_text + used, sizeof(log_text) - used, "%s\n", message);
}

bool t_log_contains(const char *text)
{
    return strstr(log_text, text) != NULL;
}

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    (void)ctx;
    if (kind != WSG_MSG_REPLY || have_line) {
        return; /* keeps the first reply of a command */
    }
    size_t n = len > 0 && line[len - 1] == '\n' ? len - 1 : len;
    ck_assert_uint_lt(n, sizeof(last_line));
    memcpy(last_line, line, n);
    last_line[n] = '\0';
    have_line = true;
}

static const wsg_conn_io_t io = {write_line};

wsg_dev_t *t_devp(void)
{
    return dev_of(&t_dev);
}

void t_start(const char *fingers)
{
    wsg_config_t cfg;
    t_now_us = T_START_US;
    next_due = 0;
    log_text[0] = '\0';
    sim_model_config(sim_model_default(), &cfg);
    sim_world_init(&t_world, &cfg, t_now_us);
    wsg_hal_t hal;
    sim_world_hal(&t_world, &hal);
    if (fingers != NULL) {
        fbus_type_t types[FBUS_SLOTS];
        finger_node_params_t params;
        finger_node_defaults(&params);
        ck_assert(finger_node_parse_pair(fingers, types));
        can_loopback_init(types, &params);
        hal.can = can_loopback_bus();
    }
    wsg_device_init(&t_dev, &cfg, &hal);
    wsg_conn_open(&conn, &t_dev, &wsg_gcl_driver, WSG_TRANSPORT_STREAM, &io, NULL);
}

void t_run_ms(uint32_t ms)
{
    for (uint32_t i = 0; i < ms; i++) {
        t_now_us += 1000u;
        sim_world_advance(&t_world, t_now_us);
        if (t_now_us >= next_due || i == 0) {
            wsg_device_step(&t_dev);
            next_due = wsg_device_next_deadline_us(&t_dev);
        }
    }
}

const char *t_ask(const char *line)
{
    char buffer[128];
    have_line = false;
    int n = snprintf(buffer, sizeof(buffer), "%s\n", line);
    wsg_conn_input(&conn, (const uint8_t *)buffer, (size_t)n);
    return have_line ? last_line : "<no reply>";
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
