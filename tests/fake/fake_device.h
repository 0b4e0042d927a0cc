/* SPDX-License-Identifier: BSD-3-Clause */
/* The fake port of the device core's Check suites: the link-time HAL (a
 * virtual clock, a captured log), one device on the simulated world, its
 * connections (fake_conn.h) and helpers that drive the world and the
 * control step in 1 ms ticks. */
#ifndef FAKE_DEVICE_H
#define FAKE_DEVICE_H

#include <check.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fake_conn.h"
#include "hal_can.h"
#include "hal_log.h"
#include "priv/wsg_dev.h"
#include "sim_world.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

#define H_LOG_MAX 64
#define H_LOG_LEN 160
#define H_START_US 5000000u /* the virtual clock does not start at zero */

extern wsg_device_t h_dev;
extern sim_world_t h_world;
extern uint64_t h_now_us;
extern h_client_t h_main; /* the session every test starts with */
extern h_client_t h_other;
extern h_client_t h_third;

/* Fixtures: power-on with h_main open; the homed variant also ran HOME(). */
void h_setup(void);
/* Power-on with a finger bus on can (NULL: none), h_main open. */
void h_setup_on_can(const hal_can_t *can);
void h_setup_homed(void);
/* Homed, with a WSG-FMF force finger in slot 0 (the host's default fingers). */
void h_setup_fmf_homed(void);
void h_teardown(void);

/* The configuration the device runs with (white box: tests may change it). */
wsg_config_t *h_cfg(void);
/* The device's private state (white box). */
wsg_dev_t *h_devp(void);

/* Opens c on h_dev with the GCL driver. */
void h_open(h_client_t *c, wsg_transport_t transport);

/* One tick per ms: advance the clock, the world, then wsg_device_step(). */
void advance_ms(uint32_t ms);
/* A control step without time passing (the port running at a deadline). */
void h_step(void);

/* Ticks until an unread line exists; returns it or "<timeout>". */
const char *await_line(h_client_t *c, uint32_t timeout_ms);
/* Ticks until `text` arrives (lines before it are skipped). Returns the
 * elapsed ms, or -1 on timeout. */
int run_until_line(h_client_t *c, const char *text, uint32_t timeout_ms);
/* Protocol shortcuts on h_main; -1 when the reply is malformed. */
int ask_flag(int bit);
int ask_gripstate(void);
float ask_float(const char *query); /* "POS?" -> value of POS=... */

bool h_log_contains(hal_log_level_t level, const char *text);
size_t h_log_count(void);

/* Elapsed virtual time since t0 in ms. */
double h_ms_since(uint64_t t0_us);

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
