/* SPDX-License-Identifier: BSD-3-Clause */
/* --sim-port: the simulation control channel, a line-based text port beside
 * the device protocol (docs/simctl.md). Loopback only unless --sim-bind. */
#ifndef SIM_CONTROL_H
#define SIM_CONTROL_H

#include <stdbool.h>

#include "coverage.h"
#include "delay.h"
#include "record.h"

/* Listens on addr:port (addr NULL: 127.0.0.1); false after a clear message. */
bool simctl_start(const char *addr, int port);
int simctl_port(void);
/* ", control 127.0.0.1:7000" for the ready line; "" without a channel. */
const char *simctl_describe(void);
/* Once per loop pass: a listener paused at the descriptor limit tries again. */
void simctl_reap(void);
void simctl_stop(void);

/* The diagnostics the channel's commands and scenarios report and write to
 * (NULL: none), handed down by main (issue 19: until the channel is an
 * instance of its own that gets them when created). */
void simctl_set_diagnostics(record_t *record, coverage_t *coverage);
record_t *simctl_record(void);
coverage_t *simctl_coverage(void);
/* The channel's injected reply delays (DELAY). */
simctl_delays_t *simctl_delays(void);

#endif
