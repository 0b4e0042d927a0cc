/* SPDX-License-Identifier: BSD-3-Clause */
/* The simulation's operations, typed: what the control channel's commands
 * (commands_world.c, commands_fault.c, commands_clock.c) do once they have
 * read their arguments, and what the web page's simulation panel
 * (host/web/web_sim.c) calls with the fields of its requests. Each checks
 * its arguments and, unless only checking, acts; false when it refuses,
 * with the status and the reason the control channel's ERR line gives. On
 * success, op->reply is the control channel's reply line to the same
 * command ("ACK PART", "AMBIENT=25"). */
#ifndef SIM_SIMCTL_OPS_H
#define SIM_SIMCTL_OPS_H

#include <stdbool.h>

#include "gripper.h"
#include "simctl_sim.h"
#include "wsg/wsg_status.h"

/* Around an operation from another front end than the control channel
 * (whose every command does the same): before, g's world brought up to
 * now, so the operation acts on the world as it is; after, g touched (its
 * deadline may have moved). */
void simctl_op_begin(gripper_t *g);
void simctl_op_end(gripper_t *g);

typedef struct {
    wsg_status_t status; /* E_SUCCESS, or why it was refused */
    char why[192];
    char reply[64];
} simctl_op_t;

/* PART(width[,stiffness[,slip_force]]): an argument not given keeps the
 * part's (or the default stiffness when there is none). */
typedef struct {
    double width_mm;
    bool stiffness_given;
    double stiffness_n_mm;
    bool slip_given;
    double slip_force_n;
} simctl_part_args_t;

bool simctl_op_part(gripper_t *g, const simctl_part_args_t *args, bool only_check, simctl_op_t *op);
bool simctl_op_part_remove(gripper_t *g, simctl_op_t *op);
bool simctl_op_part_slip(gripper_t *g, simctl_op_t *op);
bool simctl_op_obstacle(gripper_t *g, double width_mm, bool only_check, simctl_op_t *op);
bool simctl_op_obstacle_remove(gripper_t *g, simctl_op_t *op);
bool simctl_op_ambient(gripper_t *g, double celsius, bool only_check, simctl_op_t *op);

/* A fault by its name (FAULT(name[,finger])), the finger given for the
 * finger faults only: an integer 0 or 1. */
typedef struct {
    const char *name; /* NULL: none (CLEAR() of every fault) */
    bool finger_given;
    double finger;
} simctl_fault_args_t;

bool simctl_op_fault(simctl_t *ctl, gripper_t *g, const simctl_fault_args_t *args, bool only_check,
                     simctl_op_t *op);
/* CLEAR: every fault of the device, a hardware fault, or DELAY or FAILNEXT
 * (the protocol faults, which take no finger). */
bool simctl_op_clear(simctl_t *ctl, gripper_t *g, const simctl_fault_args_t *args, bool only_check,
                     simctl_op_t *op);

/* DELAY or FAILNEXT, cleared by name alone. */
bool simctl_op_protocol_fault(const char *name);

bool simctl_op_pause(simctl_t *ctl, simctl_op_t *op);
bool simctl_op_resume(simctl_t *ctl, simctl_op_t *op);
/* Starts a STEP of ms (the paused clock only): it runs on in slices from
 * the loop (simctl_step_running()). */
bool simctl_op_step(simctl_t *ctl, double ms, bool only_check, simctl_op_t *op);
bool simctl_op_scale(simctl_t *ctl, double scale, bool only_check, simctl_op_t *op);

#endif
