/* SPDX-License-Identifier: BSD-3-Clause */
/* Test harness for the simulation control commands: the real host device
 * (gripper.c) on a paused simulated clock, a GCL session on the fake port's
 * connection (tests/fake/fake_conn.h), and helpers that run control lines
 * and GCL lines. */
#ifndef SIMCTL_HARNESS_H
#define SIMCTL_HARNESS_H

#include <check.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fake_conn.h"
#include "fleet.h"
#include "gripper.h"
#include "simctl/control.h"

extern h_client_t t_gcl; /* the GCL session every test starts with */
extern simctl_t *t_sim;  /* the control side the tests drive */
extern fleet_t *t_fleet; /* the devices of t_setup */

/* Fixtures: power-on, clock paused; the homed variant also ran HOME(). */
void t_setup(void);
void t_setup_homed(void);
/* Three devices (--devices 3); t_gcl is device 0's. */
void t_setup_three_devices(void);
void t_teardown(void);
/* Opens t_gcl again (after a reset or re-init closed it). */
void t_reopen(void);
/* Device 0 powered on afresh with these options (which must outlive it), as
 * the fleet powers it on. */
void t_reinit(const host_options_t *with);

/* One control line; the reply stays valid until the next call. */
const char *ctl(const char *line);
/* The same on a channel that selected device (DEVICE=device). */
const char *ctl_on(unsigned device, const char *line);
/* Device i's system flags as the core has them (bit SF_*). */
uint32_t t_device_flags(unsigned device);
/* One GCL line from t_gcl; returns its first reply line (or "<no reply>"). */
const char *gcl(const char *line);
/* Next unread GCL line, or "<no line>". */
const char *gcl_next(void);
size_t gcl_unread(void);
/* STEP(ms) through the control channel, asserting it succeeds. */
void t_step_ms(double ms);
/* Steps 1 ms at a time until the GCL session receives `text`; ms or -1. */
int t_until(const char *text, int timeout_ms);
int t_flag(int bit);
int t_gripstate(void);
uint64_t t_now_us(void);
/* Writes text to a fresh temporary file; returns its path (static). */
const char *t_temp_file(const char *text);
/* Runs fn with stderr captured; returns what it printed (static). */
const char *t_capture_stderr(bool (*fn)(void *), void *arg, bool *result);

#define CTL_EQ(line, reply) ck_assert_str_eq(ctl(line), (reply))
#define GCL_EQ(line, reply) ck_assert_str_eq(gcl(line), (reply))
#define CTL_ERR(line, code)                                                                        \
    ck_assert_msg(t_err_code(ctl(line)) == (code), "%s: expected ERR code %d", (line), (code))

int t_err_code(const char *reply);

Suite *clock_suite(void);
Suite *world_suite(void);
Suite *faults_suite(void);
Suite *state_suite(void);
Suite *files_suite(void);

#endif
