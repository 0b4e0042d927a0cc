/* SPDX-License-Identifier: BSD-3-Clause */
/* What the fuzz targets of the host's parsers share (web routes, control
 * channel, scenario file): the host as build/wsgsim runs it, without its
 * sockets and event loop, on the paused simulated clock, started afresh for
 * every input so that each input replays alone. */
#ifndef FUZZ_HOST_H
#define FUZZ_HOST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fleet.h"
#include "options.h"
#include "simctl/control.h"

/* The host's options from argv (as main() parses them), with TCP, UDP, the
 * web server and the control channel off: NULL when they do not parse. */
host_options_t *fuzz_host_options(int argc, char **argv);
/* Logging quiet, clock paused at 0, the finger bus and the fleet started
 * (one device unless the options say more); aborts when the host fails. */
void fuzz_host_start(const host_options_t *opts);
/* One pass of the host's loop: runs what is due at the present time. */
void fuzz_host_settle(void);
/* Simulated time runs on by us, as a STEP on the control channel does; the
 * clock is paused again if something on the way resumed it. */
void fuzz_host_step(uint64_t us);
void fuzz_host_stop(void);
/* The control side started with the host (NULL while stopped). */
simctl_t *fuzz_host_sim(void);
/* The devices started with the host (NULL while stopped). */
fleet_t *fuzz_host_fleet(void);
/* The bytes as a file that the host can open by path, in $TMPDIR or
 * /dev/shm (memory): one per process, removed by fuzz_host_close_file(). */
const char *fuzz_host_file(const uint8_t *data, size_t size);
void fuzz_host_close_file(void);

#endif
