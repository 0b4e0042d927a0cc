/* SPDX-License-Identifier: BSD-3-Clause */
/* --scenario FILE: control commands at given simulated times, so a test run
 * replays the same physical story every time. Format in docs/simctl.md. */
#ifndef SIM_SCENARIO_H
#define SIM_SCENARIO_H

#include <stdbool.h>
#include <stdint.h>

/* Reads and checks the whole file (times relative to start_us); prints
 * "wsgsim: FILE:LINE: ..." and returns false on the first bad line. */
bool scenario_load(const char *path, uint64_t start_us);
/* Runs the commands due at or before now_us, in file order, at most max of
 * them; returns how many ran. */
unsigned scenario_run_due(uint64_t now_us, unsigned max);
/* When the next command is due, or UINT64_MAX. */
uint64_t scenario_next_us(void);
/* Commands not yet run. */
unsigned scenario_pending(void);
void scenario_unload(void);

#endif
