/* One virtual gripper of the host: the device core, its simulated world and
 * the configuration it powers on with, kept on the simulated clock. Every
 * entry point first brings the world up to now. An instance: the fleet holds
 * several; today main.c holds one and serves it (gripper_served()). */
#ifndef HOST_GRIPPER_H
#define HOST_GRIPPER_H

#include <stddef.h>
#include <stdint.h>

#include "options.h"
#include "sim/sim_world.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_device.h"

typedef struct {
    wsg_device_t device;
    sim_world_t world;
    wsg_config_t config; /* what a reset powers on with */
    host_options_t opts;
    uint64_t next_deadline_us;
} gripper_t;

/* Power-on state from the options (model, configuration file, part). */
void gripper_init(gripper_t *g, const host_options_t *opts);
/* Runs the control step if it is due; returns the next deadline. */
uint64_t gripper_tick(gripper_t *g);
void gripper_feed(gripper_t *g, wsg_conn_t *c, const uint8_t *bytes, size_t len,
                  int end_of_datagram);
/* Runs a control step now (the control channel changed the world). */
void gripper_step_now(gripper_t *g);
/* Power-on again: world, configuration and device state; the ports close
 * their connections first, any left over is closed here. */
void gripper_reset(gripper_t *g);

/* The instance the servers and the control channel serve (one device per
 * process until the fleet: set once by main). */
void gripper_serve(gripper_t *g);
gripper_t *gripper_served(void);

#endif
