/* SPDX-License-Identifier: BSD-3-Clause */
/* Injected hardware faults: raised and cleared from the control channel,
 * applied to the simulated world (or sent to a finger over the finger bus),
 * logged, and listed in the state dump until cleared. */
#ifndef SIM_FAULTS_H
#define SIM_FAULTS_H

#include <stdbool.h>
#include <stdint.h>

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

void simctl_fault_raise(simctl_fault_t fault);
void simctl_fault_clear(simctl_fault_t fault);
/* Clears every injected hardware fault; returns how many were active. */
unsigned simctl_fault_clear_all(void);
bool simctl_fault_active(simctl_fault_t fault);
uint64_t simctl_fault_since_us(simctl_fault_t fault);

#endif
