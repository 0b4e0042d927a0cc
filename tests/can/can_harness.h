/* SPDX-License-Identifier: BSD-3-Clause */
/* Harness of the finger-bus unit tests: a virtual clock, the device core on
 * the in-process loopback bus (host/can_loopback.c) with one GCL session,
 * and a frame tap that counts what crossed the bus. */
#ifndef CAN_HARNESS_H
#define CAN_HARNESS_H

#include <check.h>
#include <stdbool.h>
#include <stdint.h>

#include "priv/wsg_dev.h"
#include "sim/finger_node.h"
#include "sim/sim_world.h"
#include "wsg/wsg_conn.h"

extern wsg_device_t t_dev;
extern sim_world_t t_world;
/* The device's private state (white box). */
wsg_dev_t *t_devp(void);
extern uint64_t t_now_us;

/* Power-on with the given fingers on the loopback bus (NULL: no bus). */
void t_start(const char *fingers);
/* 1 ms ticks: clock, world, device step when due. */
void t_run_ms(uint32_t ms);
/* Sends one GCL line and returns the first reply line (without '\n'). */
const char *t_ask(const char *line);
/* Ticks until t_ask(line) answers `reply`; elapsed ms or -1. */
int t_until(const char *line, const char *reply, uint32_t timeout_ms);
float t_ask_float(const char *line); /* the number after '=' */
bool t_log_contains(const char *text);

Suite *proto_suite(void);
Suite *node_suite(void);
Suite *bus_suite(void);

#endif
