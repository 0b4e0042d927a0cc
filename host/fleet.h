/* SPDX-License-Identifier: BSD-3-Clause */
/* The grippers this process serves (--devices N): device i has its own
 * simulated world, device state, identity and servers, on TCP and UDP port
 * (base + i), or on free ports of its own when the base is 0. */
#ifndef HOST_FLEET_H
#define HOST_FLEET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gripper.h"
#include "loop.h"
#include "net.h"
#include "options.h"

/* Creates opts->devices grippers and starts their servers (sockets of net's,
 * watched on loop); false (logged) when a port cannot be had. */
bool fleet_start(host_loop_t *loop, net_t *net, const host_options_t *opts);
unsigned fleet_count(void);
/* Device i (i < fleet_count()). */
gripper_t *fleet_gripper(unsigned i);
/* Device i's listening ports (-1: that server is off). */
int fleet_tcp_port(unsigned i);
int fleet_udp_port(unsigned i);
/* Device i's address: the --bind address, or with --address-per-device
 * the --bind address + i. */
void fleet_device_address(unsigned i, char *out, size_t cap);
/* Device i's binary UDP port (binary port + i), -1 when not served. */
int fleet_bin_udp_port(unsigned i);
/* Steps the devices whose deadline has come; returns the earliest deadline
 * of the fleet and of its connections' timeouts (UINT64_MAX: none). */
uint64_t fleet_tick(void);
/* Closes the connections and peers of device i (a reset). */
void fleet_close_connections(unsigned i);
/* Logs one line per device after the first: "device i: tcp ADDR:P, udp
 * ADDR:P[, binary udp P], serial S, tag T". */
void fleet_announce_devices(void);
/* The ready line: device 0's ports first, as with one device (", binary
 * udp P" only when it serves binary UDP), then extra (the control channel,
 * the web server) and, for a fleet, ", devices N". */
void fleet_ready_line(const char *extra, char *line, size_t cap);
/* Scripts whose time slice ended run on for a slice each; the loop then
 * polls without blocking while one still wants to run. */
void fleet_run_scripts(void);
/* Any device may run a script (scripting configured, or started by the
 * control channel): fleet_run_scripts() has work to look for. */
void fleet_note_scripting(void);
void fleet_stop(void);

#endif
