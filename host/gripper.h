/* SPDX-License-Identifier: BSD-3-Clause */
/* One virtual gripper of the host: the device core, its simulated world and
 * the configuration it powers on with, kept on the simulated clock. Every
 * entry point first brings the world up to now. An instance: the fleet
 * (host/fleet.c) holds one per device and hands it to that device's servers. */
#ifndef HOST_GRIPPER_H
#define HOST_GRIPPER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "options.h"
#include "sim/sim_world.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_device.h"
#include "wsg/wsg_runner.h"

typedef struct gripper {
    wsg_device_t device;
    sim_world_t world;
    wsg_config_t config; /* what a reset powers on with */
    host_options_t opts;
    wsg_runner_t runner; /* feed and step: the core's, as on the board */
    bool touched;        /* on the touched list (gripper_touch) */
    struct gripper *next_touched;
    unsigned index;        /* its number in the fleet: 0 for the first */
    struct script *script; /* its script interpreter; NULL without scripting */
    char *startup_set;     /* the startup script the web page chose (heap), NULL: none chosen */
    bool startup_cleared;  /* the web page chose to run none */

    uint64_t powered_on_us; /* simulated time of its last power-on (start or reset) */
} gripper_t;

/* Power-on state from the options (model, configuration file, part) for
 * device `index` of the fleet: its serial number is the configured one plus
 * index, its tag the configured one with "-<index>" appended (device 0 keeps
 * both as configured). Only device 0 has the finger bus and the observers
 * (trace, record, coverage). */
void gripper_init(gripper_t *g, const host_options_t *opts, unsigned index);
/* Runs the control step if it is due; returns the next deadline. The fleet
 * calls it when the deadline has come or the gripper was touched. */
uint64_t gripper_tick(gripper_t *g);
void gripper_feed(gripper_t *g, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                  int end_of_datagram);
/* After input reached the device (a line, a web request): what it started
 * is due from the next simulated instant on, and the fleet ticks it. */
void gripper_input_done(gripper_t *g);
/* Something may have moved its deadline (input, a closed connection, a
 * control command): the fleet ticks it at the next pass even if not due.
 * The touched grippers form one list, taken one by one. */
void gripper_touch(gripper_t *g);
gripper_t *gripper_take_touched(void);
/* Some gripper is on the touched list (the scheduler's pass asks first). */
bool gripper_touched_any(void);
/* Runs a control step now (the control channel changed the world). */
void gripper_step_now(gripper_t *g);
/* Power-on again: world, configuration and device state; the ports close
 * their connections first, any left over is closed here. The startup
 * script runs again. */
void gripper_reset(gripper_t *g);
/* A script whose time slice ended runs on for one slice; true while it
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
/* Frees what gripper_init allocated (the script interpreter). */
void gripper_release(gripper_t *g);

#endif
