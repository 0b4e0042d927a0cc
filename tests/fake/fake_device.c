/* SPDX-License-Identifier: BSD-3-Clause */
#include "fake_device.h"

#include <stdio.h>
#include <string.h>

#include "hal_clock.h"
#include "sim_models.h"
#include "wsg/wsg_bin.h"

/* The host's table: connections opened without a driver detect one. */
static const wsg_proto_driver_t *const h_drivers[] = {&wsg_bin_driver, &wsg_gcl_driver};

wsg_device_t h_dev;
sim_world_t h_world;
uint64_t h_now_us;
h_client_t h_main;
h_client_t h_other;
h_client_t h_third;

static wsg_config_t config;

static struct {
    hal_log_level_t level[H_LOG_MAX];
    char text[H_LOG_MAX][H_LOG_LEN];
    size_t count;
} logbook;

/* hal_clock.h */
uint64_t hal_clock_now_us(void)
{
    return h_now_us;
}

/* hal_log.h */
void hal_log(hal_log_level_t level, const char *message)
{
    size_t i = logbook.count % H_LOG_MAX;
    logbook.level[i] = level;
    snprintf(logbook.text[i], H_LOG_LEN, "%s", message);
    logbook.count++;
}

static void reset_client(h_client_t *c)
{
    memset(c, 0, sizeof(*c));
}

void h_open(h_client_t *c, wsg_transport_t transport)
{
    h_open_on(c, &h_dev, &wsg_gcl_driver, transport);
}

wsg_config_t *h_cfg(void)
{
    return &h_devp()->cfg;
}

wsg_dev_t *h_devp(void)
{
    return dev_of(&h_dev);
}

void h_setup(void)
{
    h_setup_on_can(NULL);
}

void h_setup_on_can(const hal_can_t *can)
{
    memset(&logbook, 0, sizeof(logbook));
    memset(&h_dev, 0, sizeof(h_dev));
    reset_client(&h_main);
    reset_client(&h_other);
    reset_client(&h_third);
    h_now_us = H_START_US;
    wsg_sim_model_config(wsg_sim_model_default(), &config);
    wsg_sim_world_init(&h_world, &config, h_now_us);
    wsg_hal_t hal;
    wsg_sim_world_hal(&h_world, &hal);
    hal.can = can != NULL ? *can : (hal_can_t){NULL, NULL};
    wsg_device_init(&h_dev, &config, &hal);
    wsg_conn_set_drivers(&h_dev, h_drivers, sizeof(h_drivers) / sizeof(h_drivers[0]));
    h_open(&h_main, WSG_TRANSPORT_STREAM);
}

void h_setup_homed(void)
{
    h_setup();
    SEND("HOME()");
    EXPECT("ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    EXPECT_NONE();
}

void h_teardown(void)
{
    ck_assert_msg(!h_main.bad_line && !h_other.bad_line && !h_third.bad_line,
                  "a session wrote something that is not one whole line");
}

void h_step(void)
{
    wsg_sim_world_advance(&h_world, h_now_us);
    wsg_device_step(&h_dev);
}

void advance_ms(uint32_t ms)
{
    for (uint32_t i = 0; i < ms; i++) {
        h_now_us += 1000u;
        h_step();
    }
}

const char *await_line(h_client_t *c, uint32_t timeout_ms)
{
    for (uint32_t waited = 0; h_unread(c) == 0; waited++) {
        if (waited == timeout_ms) {
            return "<timeout>";
        }
        advance_ms(1);
    }
    return h_next_line(c);
}

int run_until_line(h_client_t *c, const char *text, uint32_t timeout_ms)
{
    for (uint32_t waited = 0;; waited++) {
        if (h_take_line(c, text)) {
            return (int)waited;
        }
        if (waited == timeout_ms) {
            return -1;
        }
        advance_ms(1);
    }
}

int ask_flag(int bit)
{
    char query[32];
    char expect[32];
    snprintf(query, sizeof(query), "SYSFLAGS[%d]?", bit);
    snprintf(expect, sizeof(expect), "SYSFLAGS[%d]=", bit);
    const char *reply = ask(&h_main, query);
    size_t n = strlen(expect);
    if (strncmp(reply, expect, n) != 0 || (reply[n] != '0' && reply[n] != '1') ||
        reply[n + 1] != '\0') {
        return -1;
    }
    return reply[n] - '0';
}

int ask_gripstate(void)
{
    int state = -1;
    char tail = 0;
    if (sscanf(ask(&h_main, "GRIPSTATE?"), "GRIPSTATE=%d%c", &state, &tail) != 1) {
        return -1;
    }
    return state;
}

float ask_float(const char *query)
{
    char format[40];
    float value = -1.0e9f;
    size_t n = strcspn(query, "?");
    snprintf(format, sizeof(format), "%.*s=%%f", (int)n, query);
    if (sscanf(ask(&h_main, query), format, &value) != 1) {
        return -1.0e9f;
    }
    return value;
}

bool h_log_contains(hal_log_level_t level, const char *text)
{
    size_t n = logbook.count < H_LOG_MAX ? logbook.count : H_LOG_MAX;
    for (size_t i = 0; i < n; i++) {
        if (logbook.level[i] == level && strstr(logbook.text[i], text) != NULL) {
            return true;
        }
    }
    return false;
}

size_t h_log_count(void)
{
    return logbook.count;
}

double h_ms_since(uint64_t t0_us)
{
    return (double)(h_now_us - t0_us) / 1000.0;
}
