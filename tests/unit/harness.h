/* SPDX-License-Identifier: BSD-3-Clause */
/* Test harness for the device core: a virtual clock, a captured log, fake
 * session transports that record every emitted line, and helpers that drive
 * the simulated world and the control step in 1 ms ticks. */
#ifndef HARNESS_H
#define HARNESS_H

#include <check.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal_log.h"
#include "priv/wsg_dev.h"
#include "sim_world.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

#define H_LINES_MAX 1024
#define H_LINE_LEN (WSG_REPLY_MAX + 1)
#define H_LOG_MAX 64
#define H_LOG_LEN 160
#define H_START_US 5000000u /* the virtual clock does not start at zero */

typedef struct {
    char text[H_LINE_LEN]; /* without its '\n' */
    wsg_msg_kind_t kind;
    uint64_t at_us;
} h_line_t;

typedef struct {
    wsg_conn_t conn;
    h_line_t lines[H_LINES_MAX];
    size_t count;  /* lines captured */
    size_t read;   /* lines consumed by the expect helpers */
    bool bad_line; /* a write that was not exactly one '\n'-terminated line, or overflow */
} h_client_t;

extern wsg_device_t h_dev;
extern sim_world_t h_world;
extern uint64_t h_now_us;
extern h_client_t h_main; /* the session every test starts with */
extern h_client_t h_other;
extern h_client_t h_third;

/* Fixtures: power-on with h_main open; the homed variant also ran HOME(). */
void h_setup(void);
void h_setup_homed(void);
/* Homed, with a WSG-FMF force finger in slot 0 (the host's default fingers). */
void h_setup_fmf_homed(void);
void h_teardown(void);

/* The configuration the device runs with (white box: tests may change it). */
wsg_config_t *h_cfg(void);
/* The device's private state (white box). */
wsg_dev_t *h_devp(void);

void h_open(h_client_t *c, wsg_transport_t transport);
void h_close(h_client_t *c, wsg_close_reason_t reason);
void h_send_bytes(h_client_t *c, const void *bytes, size_t len);
void send_line(h_client_t *c, const char *line); /* appends the '\n' */

/* One tick per ms: advance the clock, the world, then wsg_device_step(). */
void advance_ms(uint32_t ms);
/* A control step without time passing (the port running at a deadline). */
void h_step(void);

/* Next unread line ("<no line>" if none), and how many are unread. */
const char *h_next_line(h_client_t *c);
size_t h_unread(const h_client_t *c);
const h_line_t *h_last_read(const h_client_t *c);
/* Sends one line and returns the first line it produced. */
const char *ask(h_client_t *c, const char *line);
/* Ticks until an unread line exists; returns it or "<timeout>". */
const char *await_line(h_client_t *c, uint32_t timeout_ms);
/* Ticks until `text` arrives (lines before it are skipped). Returns the
 * elapsed ms, or -1 on timeout. */
int run_until_line(h_client_t *c, const char *text, uint32_t timeout_ms);
/* Lines captured so far that start with prefix, and drops them all as read. */
size_t h_count_prefix(h_client_t *c, const char *prefix);
void h_discard(h_client_t *c);

/* Lines the GCL driver counted in on this client's connection. */
uint32_t h_gcl_lines_in(const h_client_t *c);
uint32_t h_gcl_lines_out(const h_client_t *c);

/* Protocol shortcuts on h_main; -1 when the reply is malformed. */
int ask_flag(int bit);
int ask_gripstate(void);
float ask_float(const char *query); /* "POS?" -> value of POS=... */

bool h_log_contains(hal_log_level_t level, const char *text);
size_t h_log_count(void);

/* Elapsed virtual time since t0 in ms. */
double h_ms_since(uint64_t t0_us);

#define expect_line(c, text) ck_assert_str_eq(h_next_line(c), (text))
#define expect_no_line(c) ck_assert_msg(h_unread(c) == 0, "unexpected line \"%s\"", h_next_line(c))
#define SEND(text) send_line(&h_main, (text))
#define EXPECT(text) expect_line(&h_main, (text))
#define EXPECT_NONE() expect_no_line(&h_main)
/* A command that answers with exactly one line. */
#define ASK_EQ(line, reply)                                                                        \
    do {                                                                                           \
        ck_assert_str_eq(ask(&h_main, (line)), (reply));                                           \
        EXPECT_NONE();                                                                             \
    } while (0)
#define AWAIT(text, timeout_ms) ck_assert_str_eq(await_line(&h_main, (timeout_ms)), (text))

#endif
