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
#include "list.h"
#include "loop.h"
#include "net.h"
#include "options.h"
#include "wire.h"
#include "wsg/wsg_conn.h"

typedef struct fleet fleet_t;

/* An upper layer's hook on the devices (caller-owned node, registered
 * before fleet_start): device_started is called for each device once its
 * power-on state is set and before its startup script runs, so the
 * observers it attaches see everything the device does. */
typedef struct fleet_observer {
    void (*device_started)(void *ctx, gripper_t *g);
    /* Replies held back for this session above the port (an injected
     * DELAY); NULL: none. A half-closed TCP connection waits for them. */
    bool (*replies_held)(void *ctx, const wsg_conn_t *conn);
    /* After a control step of a device (touched or due) that left its flag
     * register (g->ticked_flags) other than its step before did, and
     * after its first step and the first after fleet_show_flags_again();
     * NULL: none. A step that changes nothing there is not shown: what the
     * observer saw then is what it sees. */
    void (*flags_changed)(void *ctx, gripper_t *g);
    void *ctx;
    list_node_t link; /* on the fleet's list */
} fleet_observer_t;

/* An empty fleet (NULL: out of memory) whose sockets will be net's, watched
 * on loop; fleet_destroy() stops what runs and frees it. */
fleet_t *fleet_create(host_loop_t *loop, net_t *net);
void fleet_destroy(fleet_t *fleet);
void fleet_observe(fleet_t *fleet, fleet_observer_t *node);
/* An observer forgot the flags it was shown (COVERAGE_RESET): each
 * device's next control step shows them again, changed or not. */
void fleet_show_flags_again(fleet_t *fleet);
/* Creates opts->devices grippers and starts their servers; false (logged)
 * when a port or a finger bus cannot be had. */
bool fleet_start(fleet_t *fleet, const host_options_t *opts);
unsigned fleet_count(const fleet_t *fleet);
/* Device i (i < fleet_count()). */
gripper_t *fleet_gripper(fleet_t *fleet, unsigned i);
/* Device i's listening ports (-1: that server is off). */
int fleet_tcp_port(const fleet_t *fleet, unsigned i);
int fleet_udp_port(const fleet_t *fleet, unsigned i);
/* Device i's address: the --bind address, or with --address-per-device
 * the --bind address + i. */
void fleet_device_address(const fleet_t *fleet, unsigned i, char *out, size_t cap);
/* Device i's binary UDP port (binary port + i), -1 when not served. */
int fleet_bin_udp_port(const fleet_t *fleet, unsigned i);
/* Steps the touched devices and, up to max_steps control steps in all, the
 * devices whose deadline has come; *steps: how many ran. Returns the
 * earliest deadline of the fleet and of its connections' timeouts
 * (UINT64_MAX: none): not later than now while due devices are left. */
uint64_t fleet_tick(fleet_t *fleet, unsigned max_steps, unsigned *steps);
/* A run of a lone device's control steps, the common stretch of a pass
 * (one device moving, nothing else due): see fleet_run_lone(). */
typedef struct {
    uint64_t *device_us; /* the device time the HAL clock reads, moved to each step */
    uint64_t before;     /* steps only at deadlines before it */
    unsigned max_steps;  /* at most this many */
    /* true ends the run; NULL: never. It may depend only on the device's
     * motion (wsg_device_motion(): its kind and start): it is asked after
     * the first step and after each that changed that motion */
    bool (*stop)(void *ctx);
    void *ctx;
    bool stopped; /* out: stop() ended the run */
} fleet_lone_run_t;

/* What fleet_tick() would do at each of the lone device's deadlines in a
 * row, with none of a pass's bookkeeping: while the device's deadline
 * comes after *device_us, before run->before and before the servers'
 * timeouts, and no device is touched, *device_us moves to it, the device
 * steps (its observers hear it) and run->stop is asked (see there: not
 * again while the motion stays as it was when last asked, as the answer
 * would not change, and a lone run takes a step per simulated ms while the
 * motion lasts). Returns how many steps ran (run->stopped: the last one's
 * stop() was true); none for a fleet of other than one device.
 * fleet_next_us() then tells the earliest deadline, as fleet_tick() would
 * have. */
unsigned fleet_run_lone(fleet_t *fleet, fleet_lone_run_t *run);
/* The earliest deadline of the fleet and of its connections' timeouts, as
 * the last fleet_tick() or fleet_run_lone() left them. */
uint64_t fleet_next_us(const fleet_t *fleet);
/* Devices whose deadline has come wait for the next fleet_tick() (its
 * budget ran out, or a script's wake-up waits for the next loop pass with
 * the device time: fleet_hold_time_for_scripts()). */
bool fleet_devices_due(const fleet_t *fleet, uint64_t now);
/* Whether a script's wake-up that the loop pass's budget cannot take holds
 * the device time until a later pass (true on a paused clock, so that a
 * STEP runs every wake-up at its instant) or runs late (a running clock).
 * docs/scripting.md, "Limits". */
void fleet_hold_time_for_scripts(fleet_t *fleet, bool hold);
/* Some device was touched since the last fleet_tick() (the scheduler's
 * pass asks first). */
bool fleet_touched_any(const fleet_t *fleet);
/* Closes the connections and peers of device i (a reset). */
void fleet_close_connections(fleet_t *fleet, unsigned i);
/* Closes what said BYE, failed or stayed quiet too long, on every device
 * (tcp_server_reap, udp_server_reap). */
void fleet_reap(fleet_t *fleet);
/* Pulls the cable of the TCP connection or forgets the UDP peer that
 * carries this session; false if none does. */
bool fleet_cut(fleet_t *fleet, const wsg_conn_t *conn);
/* Wire conditions (docs/network.md): spec for the session conn (NULL:
 * every session of every device, and those opened later); what an old
 * wire held leaves first. False when no connection or peer carries conn. */
bool fleet_set_net(fleet_t *fleet, const wsg_conn_t *conn, const wire_spec_t *spec);
/* The conditions a new session gets. */
const wire_spec_t *fleet_net(const fleet_t *fleet);
/* The seed the run's conditions draw from: their seed=, or --seed. */
uint64_t fleet_net_seed(const fleet_t *fleet);
/* The wire of the session conn (NULL: none: it has no conditions). */
const wire_t *fleet_session_wire(const fleet_t *fleet, const wsg_conn_t *conn);
/* The peer ("ADDR:PORT") that carries this session, or NULL. */
const char *fleet_peer_name(const fleet_t *fleet, const wsg_conn_t *conn);
/* The updates dropped for this session because its client did not read
 * them (a TCP queue half full, a UDP peer's budget spent), 0 if none. */
unsigned long fleet_updates_dropped(const fleet_t *fleet, const wsg_conn_t *conn);
/* Logs one line per device after the first: "device i: tcp ADDR:P, udp
 * ADDR:P[, binary udp P], serial S, tag T". */
void fleet_announce_devices(const fleet_t *fleet);
/* The ready line: device 0's ports first, as with one device (", binary
 * udp P" only when it serves binary UDP), then extra (the control channel,
 * the web server) and, for a fleet, ", devices N". */
void fleet_ready_line(const fleet_t *fleet, const char *extra, char *line, size_t cap);
/* Scripts whose time slice ended run on for a slice each; the loop then
 * polls without blocking while one still wants to run. */
void fleet_run_scripts(fleet_t *fleet);
/* Any device may run a script (scripting configured, or started by the
 * control channel): fleet_run_scripts() has work to look for. */
void fleet_note_scripting(fleet_t *fleet);
/* Stops the servers and releases the devices (the fleet can start again). */
void fleet_stop(fleet_t *fleet);

#endif
