/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulation control side: one instance holding the clock, the
 * scheduler, the scenario, the injected hardware faults and --sim-port, the
 * control channel, a line-based text port beside the device protocol
 * (docs/simctl.md). Loopback only unless --sim-bind. */
#ifndef SIM_CONTROL_H
#define SIM_CONTROL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "loop.h"
#include "net.h"
#include "simctl_sim.h"

/* The clock running at 1x from simulated time 0 (hal_clock_now_us() reads
 * it from now on), no scenario, no fault, no channel; NULL when out of
 * memory. */
simctl_t *simctl_create(void);
/* Closes the channel, unloads the scenario, frees the instance. */
void simctl_destroy(simctl_t *ctl);

/* The devices it drives and addresses, before simctl_tick() and the
 * channel's commands run. */
void simctl_set_fleet(simctl_t *ctl, struct fleet *fleet);

/* Listens on addr:port (addr NULL: 127.0.0.1; a socket of net's, watched on
 * loop); false after a clear message. */
bool simctl_start(simctl_t *ctl, host_loop_t *loop, net_t *net, const char *addr, int port);
int simctl_port(const simctl_t *ctl);
/* ", control 127.0.0.1:7000" for the ready line into out; "" without a
 * channel. */
void simctl_describe(const simctl_t *ctl, char *out, size_t cap);
/* After the pass's simulated work (simctl_settle()), outside the loop's
 * callbacks: a STEP that ended in it is answered and the commands the
 * connections queued meanwhile run (one may start the next STEP). False
 * when no STEP had ended; true: the loop should not sleep, the next pass
 * settles what those commands did. */
bool simctl_answer_steps(simctl_t *ctl);
/* Once per loop pass: a listener paused at the descriptor limit tries again. */
void simctl_reap(simctl_t *ctl);
void simctl_stop(simctl_t *ctl);

/* The diagnostics the channel's commands, scenarios and scheduler report
 * and write to (NULL: none), handed down by main once they exist. */
void simctl_set_diagnostics(simctl_t *ctl, record_t *record, coverage_t *coverage);

#endif
