/* SPDX-License-Identifier: BSD-3-Clause */
/* One virtual gripper of the host: the device core, its simulated world and
 * the configuration it powers on with, kept on the simulated clock. Every
 * entry point first brings the world up to now. An instance: the fleet
 * (host/port/fleet.c) holds one per device and hands it to that device's servers.
 * Each gripper is a whole device: its own finger bus with its fingers. */
#ifndef HOST_GRIPPER_H
#define HOST_GRIPPER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "finger_bus_host.h"
#include "list.h"
#include "options.h"
#include "physics_world.h"
#include "sim/sim_world.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_device.h"
#include "wsg/wsg_runner.h"
#include "wsg/wsg_timing.h"

struct gripper;
/* The grippers touched since they were last ticked: one list per fleet,
 * which hands it to its grippers (gripper_init). */
typedef struct {
    list_t grippers; /* the last touched first */
} gripper_touched_t;

/* What follows the device's control steps (the --record's samples of its
 * state): called after each step that ran, with the gripper's index in the
 * fleet. Steps left out while coasting are not seen; their readings stay
 * within the envelope of the steps around them (wsg_device_coast()). */
typedef struct {
    void (*stepped)(void *ctx, unsigned index, wsg_device_t *dev);
    void *ctx;
} gripper_step_hook_t;

/* No flag register (which has 32 bits) was shown. */
#define GRIPPER_FLAGS_UNSHOWN UINT64_MAX

typedef struct gripper {
    wsg_device_t device;
    sim_world_t world;
    wsg_config_t config; /* what a reset powers on with */
    /* --physics mujoco: the axis and the fingers' readings come from this
     * physics scene (docs/physics.md); NULL: the built-in world's */
    physics_world_t *physics;
    /* its options: the fleet's, or its own copy (own_opts) once they differ
     * (a [device.N] model, script or fingers; a startup script chosen on the
     * web page), so a fleet of alike devices keeps one copy */
    const host_options_t *opts;
    host_options_t *own_opts;
    wsg_runner_t runner;       /* feed and step: the core's, as on the board */
    finger_bus_host_t fingers; /* its finger bus */
    list_node_t touched_link;  /* on touched_list while touched */
    gripper_touched_t *touched_list;
    /* the limits every script of the process shares (the fleet's) */
    struct script_guard *script_guard;
    /* the flag register the fleet's observers saw last (host/port/fleet.c);
     * GRIPPER_FLAGS_UNSHOWN: none since its start or an observer forgot */
    uint64_t shown_flags;
    uint32_t ticked_flags;                /* the flag register its last tick left: 0 before */
    unsigned index;                       /* its number in the fleet: 0 for the first */
    struct script *script;                /* its script interpreter; NULL without scripting */
    const gripper_step_hook_t *step_hook; /* NULL: none (a plain run) */
    char *startup_set;      /* the startup script the web page chose (heap), NULL: none chosen */
    char *timing_set;       /* the timing profile TIMING= chose (heap), NULL: the options' */
    uint64_t powered_on_us; /* simulated time of its last power-on (start or reset) */
    /* the small fields last, together: a cell holds 10 000 grippers */
    bool touched;         /* on the touched list (gripper_touch) */
    bool startup_cleared; /* the web page chose to run none */
} gripper_t;

/* Power-on state from the options (model, configuration file, part) for
 * device `index` of the fleet: its serial number is the configured one plus
 * index, its tag the configured one with "-<index>" appended (device 0 keeps
 * both as configured). Its finger bus: SocketCAN for device 0 with --can,
 * else a loopback bus with its fingers ([device.N] fingers, or --fingers).
 * opts must outlive the gripper (it keeps a pointer, and copies them only
 * once its own differ). gripper_touch() puts it on `touched`. False (logged) when its finger bus
 * cannot be had; gripper_release() it all the same. Observers attach next,
 * then gripper_start() runs the startup script. Its scripts run under
 * `guard` (the fleet's: it outlives the gripper). */
bool gripper_init(gripper_t *g, host_loop_t *loop, const host_options_t *opts, unsigned index,
                  gripper_touched_t *touched, struct script_guard *guard);
/* Runs the startup script (--script), as at power-on. */
void gripper_start(gripper_t *g);
/* Runs the control step if it is due; returns the next deadline. The fleet
 * calls it when the deadline has come or the gripper was touched. */
uint64_t gripper_tick(gripper_t *g);
/* gripper_tick() with the world at the clock already (gripper_coasts_at()). */
uint64_t gripper_tick_advanced(gripper_t *g);
/* Right after a tick: whether later ticks may coast, and within what
 * (wsg_device_coast(); never while a script runs: it is served each tick). */
bool gripper_may_coast(const gripper_t *g, wsg_coast_t *coast);
/* Coasting at at_us, an instant before coast->until_us that is not the
 * last before anything else meets the device: the world advances to it;
 * true when its readings are within the envelope, so that the step may be
 * left out, else the caller ticks with gripper_tick_advanced() at at_us. */
bool gripper_coasts_at(gripper_t *g, const wsg_coast_t *coast, uint64_t at_us);
/* Coasting at at_us and the instants a tick after it, while only the
 * jaws' position moves (wsg_sim_world_cruise()), at most max of them: 0
 * unless at_us is a tick after the world's last advance. Returns how many
 * the world advanced to; *outside: the last of them is outside the
 * envelope, and its step runs next (gripper_tick_advanced()). */
unsigned gripper_cruise(gripper_t *g, const wsg_coast_t *coast, uint64_t at_us, unsigned max,
                        bool *outside);
/* After the steps left out, the last at last_us: the device notes them
 * (wsg_device_coasted()), the runner's next deadline is the step after. */
void gripper_coasted(gripper_t *g, const wsg_coast_t *coast, uint64_t last_us);
/* Input on one of its connections, at the present instant; touches g
 * unless its tick would have nothing to do (a query that changed nothing:
 * neither a step due nor a new deadline, no flag its observers have not
 * seen, no script, no DELAY on c's output). */
/* Returns the bytes c took: fewer than len only under a timing profile,
 * while a request of c waits for the device's command processor; the
 * caller keeps the rest (held_input.h). */
size_t gripper_feed(gripper_t *g, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                    int end_of_datagram);
/* After input reached the device (a line, a web request): what it started
 * is due from the next simulated instant on, and the fleet ticks it. */
void gripper_input_done(gripper_t *g);
/* Something may have moved its deadline (input, a closed connection, a
 * control command): the fleet ticks it at the next pass even if not due.
 * The touched grippers form one list, taken one by one. */
void gripper_touch(gripper_t *g);
gripper_t *gripper_take_touched(gripper_touched_t *touched);
/* Runs a control step now (the control channel changed the world). */
void gripper_step_now(gripper_t *g);
/* Power-on again: world, configuration and device state; the ports close
 * their connections first, any left over is closed here. The startup
 * script runs again. */
void gripper_reset(gripper_t *g);
/* Raises or clears an injected fault of the finger in slot 0 or 1
 * (finger_bus_host_inject); a loopback bus is brought up to now first and
 * the device steps to see it take effect. False: bad slot, no bus. */
bool gripper_inject_finger_fault(gripper_t *g, unsigned slot, finger_fault_t fault, bool active);
/* A script whose time slice ended runs on for one slice when it has its
 * turn (the scripts share one slice budget per loop pass); true while it
 * still wants to run (the loop must not block). */
bool gripper_continue_script(gripper_t *g);
/* Runs a script file on the device (docs/scripting.md); false with *why. */
bool gripper_run_script(gripper_t *g, const char *file, char *why, size_t cap);
/* The startup script from now on (the next power-on runs it): a file of
 * the /user/ store ("/user/NAME"), or none (NULL); false with *why when it
 * is no store file. Chosen on the web page; Save keeps it. */
bool gripper_set_startup(gripper_t *g, const char *file, char *why, size_t cap);
/* What the web page chose, for Save: the file, "" for none, NULL when it
 * chose nothing (the options' startup script stands). */
const char *gripper_startup_choice(const gripper_t *g);
/* Frees what gripper_init allocated (finger bus, script interpreter). */
void gripper_release(gripper_t *g);

/* The device's pace now (TIMING=): the profile's name or path and its
 * figures (their seed the device's own); false out of memory. */
bool gripper_set_timing(gripper_t *g, const char *spec, const wsg_timing_t *timing);
/* The name or path of the profile in force ("ideal" by default). */
const char *gripper_timing_name(const gripper_t *g);

#endif
