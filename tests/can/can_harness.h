/* SPDX-License-Identifier: BSD-3-Clause */
/* The finger-bus unit tests on the fake port (tests/fake/fake_device.h):
 * the device core on the in-process loopback bus (host/can/can_loopback.c),
 * stepped only when due as a port steps it, and GCL shortcuts on h_main. */
#ifndef CAN_HARNESS_H
#define CAN_HARNESS_H

#include <check.h>
#include <stdbool.h>
#include <stdint.h>

#include "fake_device.h"
#include "sim/finger_node.h"

/* The loopback bus the last t_start powered on with (the previous one is
 * freed by the next t_start). */
struct can_loopback *t_bus(void);
/* Power-on with the given fingers on the loopback bus (NULL: no bus). */
void t_start(const char *fingers);
/* t_start, on a bus that loses the gripper's first `lost` TARE commands
 * before any finger sees them (a node's full receive queue). */
void t_start_losing_tares(const char *fingers, unsigned lost);
/* TARE commands the gripper sent since t_start_losing_tares, lost included. */
unsigned t_tares_sent(void);
/* t_start, on the loopback bus presented as a real one (not on demand): the
 * gripper steps it every 10 ms, as it does a SocketCAN bus. */
void t_start_real_time(const char *fingers);
/* t_start, on the loopback bus behind a controller that counts the polls
 * the core makes (t_polls) and the skipped ones it tells (t_skips_told:
 * how many times, and the last time told). */
void t_start_counting_polls(const char *fingers);
unsigned t_polls(void);
unsigned t_skips_told(uint64_t *last_us);
/* While held, the fingers of that bus do not run: nothing reaches the gripper. */
void t_hold_fingers(bool held);
/* 1 ms ticks: clock, world, device step when due. */
void t_run_ms(uint32_t ms);
/* Sends one GCL line and returns its first reply line (updates skipped). */
const char *t_ask(const char *line);
/* Ticks until t_ask(line) answers `reply`; elapsed ms or -1. */
int t_until(const char *line, const char *reply, uint32_t timeout_ms);
float t_ask_float(const char *line); /* the number after '=' */
/* A log message at any level contains text. */
bool t_log_contains(const char *text);

Suite *proto_suite(void);
Suite *node_suite(void);
Suite *bus_suite(void);
Suite *loopback_suite(void);

#endif
