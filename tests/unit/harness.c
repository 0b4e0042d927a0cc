/* SPDX-License-Identifier: BSD-3-Clause */
#include "harness.h"

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

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    h_client_t *c = ctx;
    bool one_line =
        len > 0 && line[len - 1] == '\n' && memchr(line, '\n', len - 1) == NULL && len < H_LINE_LEN;
    if (!one_line || c->count == H_LINES_MAX) {
        c->bad_line = true;
        return;
    }
    h_line_t *out = &c->lines[c->count++];
    memcpy(out->text, line, len - 1);
    out->text[len - 1] = '\0';
    out->kind = kind;
    out->at_us = h_now_us;
}

static const wsg_conn_io_t capture_io = {write_line};

static void reset_client(h_client_t *c)
{
    memset(c, 0, sizeof(*c));
}

void h_open(h_client_t *c, wsg_transport_t transport)
{
    reset_client(c);
    wsg_conn_open(&c->conn, &h_dev, &wsg_gcl_driver, transport, &capture_io, c);
}

void h_close(h_client_t *c, wsg_close_reason_t reason)
{
    wsg_conn_close(&c->conn, reason);
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
    memset(&logbook, 0, sizeof(logbook));
    memset(&h_dev, 0, sizeof(h_dev));
    reset_client(&h_main);
    reset_client(&h_other);
    reset_client(&h_third);
    h_now_us = H_START_US;
    sim_model_config(sim_model_default(), &config);
    sim_world_init(&h_world, &config, h_now_us);
    wsg_hal_t hal;
    sim_world_hal(&h_world, &hal);
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

void h_send_bytes(h_client_t *c, const void *bytes, size_t len)
{
    wsg_conn_input(&c->conn, bytes, len);
}

void send_line(h_client_t *c, const char *line)
{
    char buf[1024];
    size_t len = strlen(line);
    ck_assert_uint_lt(len, sizeof(buf));
    memcpy(buf, line, len);
    buf[len] = '\n';
    h_send_bytes(c, buf, len + 1);
}

void h_step(void)
{
    sim_world_advance(&h_world, h_now_us);
    wsg_device_step(&h_dev);
}

void advance_ms(uint32_t ms)
{
    for (uint32_t i = 0; i < ms; i++) {
        h_now_us += 1000u;
        h_step();
    }
}

size_t h_unread(const h_client_t *c)
{
    return c->count - c->read;
}

const char *h_next_line(h_client_t *c)
{
    if (c->read == c->count) {
        return "<no line>";
    }
    return c->lines[c->read++].text;
}

const h_line_t *h_last_read(const h_client_t *c)
{
    return c->read > 0 ? &c->lines[c->read - 1] : NULL;
}

const char *ask(h_client_t *c, const char *line)
{
    size_t before = c->count;
    send_line(c, line);
    if (c->count == before) {
        return "<no reply>";
    }
    return h_next_line(c);
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

static bool take_line(h_client_t *c, const char *text)
{
    while (c->read < c->count) {
        if (strcmp(c->lines[c->read++].text, text) == 0) {
            return true;
        }
    }
    return false;
}

int run_until_line(h_client_t *c, const char *text, uint32_t timeout_ms)
{
    for (uint32_t waited = 0;; waited++) {
        if (take_line(c, text)) {
            return (int)waited;
        }
        if (waited == timeout_ms) {
            return -1;
        }
        advance_ms(1);
    }
}

size_t h_count_prefix(h_client_t *c, const char *prefix)
{
    size_t n = 0;
    for (size_t i = c->read; i < c->count; i++) {
        if (strncmp(c->lines[i].text, prefix, strlen(prefix)) == 0) {
            n++;
        }
    }
    return n;
}

void h_discard(h_client_t *c)
{
    c->read = c->count;
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

uint32_t h_gcl_lines_in(const h_client_t *c)
{
    wsg_gcl_conn_info_t info;
    ck_assert(wsg_gcl_conn_info(&c->conn, &info));
    return info.lines_in;
}

uint32_t h_gcl_lines_out(const h_client_t *c)
{
    wsg_gcl_conn_info_t info;
    ck_assert(wsg_gcl_conn_info(&c->conn, &info));
    return info.lines_out;
}
