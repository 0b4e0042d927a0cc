/* SPDX-License-Identifier: BSD-3-Clause */
/* Injected hardware faults: raised and cleared from the control channel,
 * applied to one device's simulated world (or sent to a finger over its
 * finger bus), logged, and listed in the state dump until cleared. Every
 * device has its own; a device's record is allocated when it first takes a
 * fault, so an idle fleet pays one pointer per device at most. */
#ifndef SIM_FAULTS_H
#define SIM_FAULTS_H

#include <stdbool.h>
#include <stdint.h>

#include "gripper.h"

typedef enum {
    SIMCTL_FAULT_TEMP_WARNING, /* board temperature between warning and fault level */
    SIMCTL_FAULT_TEMP_FAULT,   /* board temperature above the fault level */
    SIMCTL_FAULT_POWER,        /* supply voltage out of range */
    SIMCTL_FAULT_CURRENT,      /* motor over-current */
    /* finger faults, raised by the finger itself on the finger bus */
    SIMCTL_FAULT_FINGER0_POWER, /* over-current: FF_POWER_FAULT */
    SIMCTL_FAULT_FINGER1_POWER,
    SIMCTL_FAULT_FINGER0_INIT, /* cannot initialise: FF_INIT_FAULT */
    SIMCTL_FAULT_FINGER1_INIT,
    SIMCTL_FAULT_FINGER0_UNPLUG, /* leaves the bus: FF_COMM_FAULT */
    SIMCTL_FAULT_FINGER1_UNPLUG,
    SIMCTL_FAULT_COUNT
} simctl_fault_t;

/* "TEMP_WARNING", "TEMP_FAULT", "POWER", "CURRENT", or a finger fault
 * "FINGER_POWER" (alias "FINGER"), "FINGER_INIT", "FINGER_UNPLUG" with finger
 * 0 or 1. Case-insensitive. */
bool simctl_fault_by_name(const char *name, int finger, simctl_fault_t *out);
const char *simctl_fault_name(simctl_fault_t fault);
const char *simctl_fault_description(simctl_fault_t fault);

struct simctl_device_faults;

/* The faults of every device, indexed by the device's number in the fleet. */
typedef struct {
    struct simctl_device_faults **of; /* NULL: that device never took one */
    unsigned count;                   /* entries in of */
} simctl_faults_t;

void simctl_faults_init(simctl_faults_t *faults);
/* Frees every device's record (nothing is applied to the worlds). */
void simctl_faults_release(simctl_faults_t *faults);

/* True when the device can take the fault: a finger fault needs the
 * device's finger bus (only device 0 has one). */
bool simctl_fault_possible(const gripper_t *g, simctl_fault_t fault);
/* False (nothing changed) when memory for the device's record ran out. */
bool simctl_fault_raise(simctl_faults_t *faults, gripper_t *g, simctl_fault_t fault);
void simctl_fault_clear(simctl_faults_t *faults, gripper_t *g, simctl_fault_t fault);
/* Clears every injected hardware fault of the device; returns how many
 * were active. */
unsigned simctl_fault_clear_all(simctl_faults_t *faults, gripper_t *g);
bool simctl_fault_active(const simctl_faults_t *faults, const gripper_t *g, simctl_fault_t fault);
uint64_t simctl_fault_since_us(const simctl_faults_t *faults, const gripper_t *g,
                               simctl_fault_t fault);

#endif
