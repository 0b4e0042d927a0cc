/* SPDX-License-Identifier: BSD-3-Clause */
/* --sim-port: the simulation control channel, a line-based text port beside
 * the device protocol (docs/simctl.md). Loopback only unless --sim-bind. */
#ifndef SIM_CONTROL_H
#define SIM_CONTROL_H

#include <stdbool.h>

#include "loop.h"
#include "net.h"

/* Listens on addr:port (addr NULL: 127.0.0.1; a socket of net's, watched on
 * loop); false after a clear message. */
bool simctl_start(host_loop_t *loop, net_t *net, const char *addr, int port);
int simctl_port(void);
/* ", control 127.0.0.1:7000" for the ready line; "" without a channel. */
const char *simctl_describe(void);
/* Once per loop pass: a listener paused at the descriptor limit tries again. */
void simctl_reap(void);
void simctl_stop(void);

#endif
