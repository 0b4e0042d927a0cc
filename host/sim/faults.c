/* SPDX-License-Identifier: BSD-3-Clause */
#include "faults.h"
#include "fleet.h"

#include <strings.h>

#include "finger_bus_host.h"
#include "gripper.h"
#include "hal_clock.h"
#include "log.h"
#include "scheduler.h"
#include "sim/sim_world.h"

#define NO_OVERRIDE (-1000.0f)
#define TEMP_FAULT_MARGIN_C 5.0f

static const struct {
    const char *name;
    const char *description;
} info[SIMCTL_FAULT_COUNT] = {
    [SIMCTL_FAULT_TEMP_WARNING] = {"TEMP_WARNING", "board temperature above the warning level"},
    [SIMCTL_FAULT_TEMP_FAULT] = {"TEMP_FAULT", "board temperature above the critical level"},
    [SIMCTL_FAULT_POWER] = {"POWER", "power supply out of range"},
    [SIMCTL_FAULT_CURRENT] = {"CURRENT", "motor over-current"},
    [SIMCTL_FAULT_FINGER0_POWER] = {"FINGER0_POWER", "finger 0 over-current"},
    [SIMCTL_FAULT_FINGER1_POWER] = {"FINGER1_POWER", "finger 1 over-current"},
    [SIMCTL_FAULT_FINGER0_INIT] = {"FINGER0_INIT", "finger 0 cannot initialise"},
    [SIMCTL_FAULT_FINGER1_INIT] = {"FINGER1_INIT", "finger 1 cannot initialise"},
    [SIMCTL_FAULT_FINGER0_UNPLUG] = {"FINGER0_UNPLUG", "finger 0 left the bus"},
    [SIMCTL_FAULT_FINGER1_UNPLUG] = {"FINGER1_UNPLUG", "finger 1 left the bus"},
};

/* FINGER_<kind> with an index names FINGER<index>_<kind>. */
static const struct {
    const char *name;
    simctl_fault_t first; /* finger 0; finger 1 follows it */
} finger_kinds[] = {
    {"FINGER", SIMCTL_FAULT_FINGER0_POWER},
    {"FINGER_POWER", SIMCTL_FAULT_FINGER0_POWER},
    {"FINGER_INIT", SIMCTL_FAULT_FINGER0_INIT},
    {"FINGER_UNPLUG", SIMCTL_FAULT_FINGER0_UNPLUG},
};

static struct {
    bool active[SIMCTL_FAULT_COUNT];
    uint64_t since_us[SIMCTL_FAULT_COUNT];
} faults;

bool simctl_fault_by_name(const char *name, int finger, simctl_fault_t *out)
{
    for (unsigned i = 0; i < sizeof(finger_kinds) / sizeof(finger_kinds[0]); i++) {
        if (strcasecmp(name, finger_kinds[i].name) == 0 && (finger == 0 || finger == 1)) {
            *out = (simctl_fault_t)(finger_kinds[i].first + finger);
            return true;
        }
    }
    for (unsigned i = 0; i < SIMCTL_FAULT_COUNT; i++) {
        if (strcasecmp(name, info[i].name) == 0) {
            *out = (simctl_fault_t)i;
            return true;
        }
    }
    return false;
}

const char *simctl_fault_name(simctl_fault_t fault)
{
    return (unsigned)fault < SIMCTL_FAULT_COUNT ? info[fault].name : "?";
}

const char *simctl_fault_description(simctl_fault_t fault)
{
    return (unsigned)fault < SIMCTL_FAULT_COUNT ? info[fault].description : "?";
}

/* The board temperature the active temperature faults force. */
static void apply_temperature(void)
{
    const wsg_config_t *cfg =
        wsg_device_snapshot(&fleet_gripper(simctl_fleet(), 0)->device)->config;
    sim_thermal_t *thermal = &fleet_gripper(simctl_fleet(), 0)->world.thermal;
    thermal->override_c = NO_OVERRIDE;
    if (faults.active[SIMCTL_FAULT_TEMP_WARNING]) {
        thermal->override_c = (cfg->temp_warning_c + cfg->temp_fault_c) / 2.0f;
    }
    if (faults.active[SIMCTL_FAULT_TEMP_FAULT]) {
        thermal->override_c = cfg->temp_fault_c + TEMP_FAULT_MARGIN_C;
    }
}

/* The finger itself raises it: a fault-injection frame on the finger bus. */
static void apply_finger(simctl_fault_t fault, bool on)
{
    unsigned index = (unsigned)(fault - SIMCTL_FAULT_FINGER0_POWER);
    unsigned slot = index % 2u;
    static const finger_fault_t kinds[] = {FINGER_FAULT_POWER, FINGER_FAULT_INIT,
                                           FINGER_FAULT_UNPLUG};
    if (!gripper_inject_finger_fault(fleet_gripper(simctl_fleet(), 0), slot, kinds[index / 2u],
                                     on)) {
        host_logf(HAL_LOG_WARN, "finger %u: the finger bus did not take the fault", slot);
    }
}

static void apply(simctl_fault_t fault)
{
    bool on = faults.active[fault];
    sim_axis_t *axis = &fleet_gripper(simctl_fleet(), 0)->world.axis;
    switch (fault) {
    case SIMCTL_FAULT_TEMP_WARNING:
    case SIMCTL_FAULT_TEMP_FAULT:
        apply_temperature();
        break;
    case SIMCTL_FAULT_POWER:
        axis->power_fault = on;
        break;
    case SIMCTL_FAULT_CURRENT:
        axis->current_fault = on;
        break;
    case SIMCTL_FAULT_COUNT:
        break;
    default:
        apply_finger(fault, on);
        break;
    }
}

void simctl_fault_raise(simctl_fault_t fault)
{
    if (!faults.active[fault]) {
        faults.active[fault] = true;
        faults.since_us[fault] = hal_clock_now_us();
    }
    apply(fault);
    host_logf(HAL_LOG_WARN, "fault injected: %s (%s)", info[fault].name, info[fault].description);
}

void simctl_fault_clear(simctl_fault_t fault)
{
    if (!faults.active[fault]) {
        return;
    }
    faults.active[fault] = false;
    apply(fault);
    host_logf(HAL_LOG_INFO, "fault cleared: %s", info[fault].name);
}

unsigned simctl_fault_clear_all(void)
{
    unsigned cleared = 0;
    for (unsigned i = 0; i < SIMCTL_FAULT_COUNT; i++) {
        cleared += faults.active[i] ? 1u : 0u;
        simctl_fault_clear((simctl_fault_t)i);
    }
    return cleared;
}

bool simctl_fault_active(simctl_fault_t fault)
{
    return (unsigned)fault < SIMCTL_FAULT_COUNT && faults.active[fault];
}

uint64_t simctl_fault_since_us(simctl_fault_t fault)
{
    return simctl_fault_active(fault) ? faults.since_us[fault] : 0u;
}
