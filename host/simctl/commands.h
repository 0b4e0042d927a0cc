/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulation control commands (docs/simctl.md): one line in, one reply
 * line out, with the lexical rules of GCL. */
#ifndef SIM_COMMANDS_H
#define SIM_COMMANDS_H

#include <stdbool.h>
#include <stddef.h>

#include "simctl_sim.h"

typedef struct {
    bool close;    /* the line asked to end the channel (BYE) */
    bool deferred; /* a STEP or RUN_UNTIL_DONE runs on: its reply is
                    * simctl_step_reply() once simctl_step_running() turns false */
} simctl_outcome_t;

/* Runs one control line (without its terminator) and returns the reply line
 * (malloc'd, no '\n'): "ACK NAME", "NAME=value" or "ERR NAME code reason".
 * selected: the channel's device (DEVICE= changes it); NULL: device 0.
 * With an outcome, a STEP only starts: NULL is returned and the STEP runs in
 * slices from the event loop. Without one, a STEP runs to its end first. */
char *simctl_exec(simctl_t *ctl, const char *line, size_t len, unsigned *selected,
                  simctl_outcome_t *outcome);
/* "STEP=<simulated ms>" or "RUN_UNTIL_DONE=[ms,\"why\"]", the reply of the step
 * that has run (malloc'd). */
char *simctl_step_reply(simctl_t *ctl);

/* True when the line is a known control command in a form it accepts, with
 * valid arguments (checked without acting; a session id only for its form);
 * else why not. for_scenario also refuses commands a scenario cannot run. */
bool simctl_check(simctl_t *ctl, const char *line, size_t len, bool for_scenario, char *why,
                  size_t cap);

#endif
