/* SPDX-License-Identifier: BSD-3-Clause */
#include "faults.h"

#include <stdio.h>
#include <stdlib.h>
#include <strings.h>

#include "finger_bus_host.h"
#include "gripper.h"
#include "hal_clock.h"
#include "log.h"
#include "sim/sim_world.h"

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

/* One device's faults. */
struct simctl_device_faults {
    bool active[SIMCTL_FAULT_COUNT];
    uint64_t since_us[SIMCTL_FAULT_COUNT];
};

void simctl_faults_init(simctl_faults_t *faults)
{
    *faults = (simctl_faults_t){NULL, 0};
}

void simctl_faults_release(simctl_faults_t *faults)
{
    for (unsigned i = 0; i < faults->count; i++) {
        free(faults->of[i]);
    }
    free(faults->of);
    simctl_faults_init(faults);
}

/* The device's record, or NULL when it never took a fault. */
static struct simctl_device_faults *record_of(const simctl_faults_t *faults, const gripper_t *g)
{
    return g->index < faults->count ? faults->of[g->index] : NULL;
}

/* The device's record, allocated on its first fault; NULL: out of memory. */
static struct simctl_device_faults *record_for(simctl_faults_t *faults, const gripper_t *g)
{
    if (g->index >= faults->count) {
        unsigned count = g->index + 1u;
        struct simctl_device_faults **grown = realloc(faults->of, count * sizeof(*grown));
        if (grown == NULL) {
            return NULL;
        }
        for (unsigned i = faults->count; i < count; i++) {
            grown[i] = NULL;
        }
        faults->of = grown;
        faults->count = count;
    }
    if (faults->of[g->index] == NULL) {
        faults->of[g->index] = calloc(1, sizeof(struct simctl_device_faults));
    }
    return faults->of[g->index];
}

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
static void apply_temperature(const struct simctl_device_faults *f, gripper_t *g)
{
    const wsg_config_t *cfg = wsg_device_snapshot(&g->device)->config;
    sim_thermal_t *thermal = &g->world.thermal;
    if (f->active[SIMCTL_FAULT_TEMP_FAULT]) {
        wsg_sim_thermal_override(thermal, cfg->temp_fault_c + TEMP_FAULT_MARGIN_C);
    } else if (f->active[SIMCTL_FAULT_TEMP_WARNING]) {
        wsg_sim_thermal_override(thermal, (cfg->temp_warning_c + cfg->temp_fault_c) / 2.0f);
    } else {
        wsg_sim_thermal_clear_override(thermal);
    }
}

static bool is_finger_fault(simctl_fault_t fault)
{
    return fault >= SIMCTL_FAULT_FINGER0_POWER && fault < SIMCTL_FAULT_COUNT;
}

/* A finger fault needs the device's finger bus; device 0 takes one without
 * a bus as before (the injection then logs that no bus took it). */
bool simctl_fault_possible(const gripper_t *g, simctl_fault_t fault)
{
    return !is_finger_fault(fault) || g->index == 0 || finger_bus_host_can(&g->fingers) != NULL;
}

/* The finger itself raises it: a fault-injection frame on the finger bus. */
static void apply_finger(gripper_t *g, simctl_fault_t fault, bool on)
{
    unsigned index = (unsigned)(fault - SIMCTL_FAULT_FINGER0_POWER);
    unsigned slot = index % 2u;
    static const finger_fault_t kinds[] = {FINGER_FAULT_POWER, FINGER_FAULT_INIT,
                                           FINGER_FAULT_UNPLUG};
    if (!gripper_inject_finger_fault(g, slot, kinds[index / 2u], on)) {
        host_logf(HAL_LOG_WARN, "finger %u: the finger bus did not take the fault", slot);
    }
}

/* " on device N" after a log line, except for device 0 (its lines stay as
 * they were with one device). */
static const char *device_note(const gripper_t *g, char *note, size_t cap)
{
    note[0] = '\0';
    if (g->index != 0) {
        snprintf(note, cap, " on device %u", g->index);
    }
    return note;
}

static void apply(const struct simctl_device_faults *f, gripper_t *g, simctl_fault_t fault)
{
    bool on = f->active[fault];
    sim_axis_t *axis = &g->world.axis;
    switch (fault) {
    case SIMCTL_FAULT_TEMP_WARNING:
    case SIMCTL_FAULT_TEMP_FAULT:
        apply_temperature(f, g);
        break;
    case SIMCTL_FAULT_POWER:
        wsg_sim_axis_set_power_fault(axis, on);
        break;
    case SIMCTL_FAULT_CURRENT:
        wsg_sim_axis_set_current_fault(axis, on);
        break;
    case SIMCTL_FAULT_COUNT:
        break;
    default:
        apply_finger(g, fault, on);
        break;
    }
}

bool simctl_fault_raise(simctl_faults_t *faults, gripper_t *g, simctl_fault_t fault)
{
    struct simctl_device_faults *f = record_for(faults, g);
    if (f == NULL) {
        return false;
    }
    if (!f->active[fault]) {
        f->active[fault] = true;
        f->since_us[fault] = hal_clock_now_us();
    }
    apply(f, g, fault);
    char note[32];
    host_logf(HAL_LOG_WARN, "fault injected: %s (%s)%s", info[fault].name, info[fault].description,
              device_note(g, note, sizeof(note)));
    return true;
}

void simctl_fault_clear(simctl_faults_t *faults, gripper_t *g, simctl_fault_t fault)
{
    struct simctl_device_faults *f = record_of(faults, g);
    if (f == NULL || !f->active[fault]) {
        return;
    }
    f->active[fault] = false;
    apply(f, g, fault);
    char note[32];
    host_logf(HAL_LOG_INFO, "fault cleared: %s%s", info[fault].name,
              device_note(g, note, sizeof(note)));
}

unsigned simctl_fault_clear_all(simctl_faults_t *faults, gripper_t *g)
{
    unsigned cleared = 0;
    for (unsigned i = 0; i < SIMCTL_FAULT_COUNT; i++) {
        cleared += simctl_fault_active(faults, g, (simctl_fault_t)i) ? 1u : 0u;
        simctl_fault_clear(faults, g, (simctl_fault_t)i);
    }
    return cleared;
}

bool simctl_fault_active(const simctl_faults_t *faults, const gripper_t *g, simctl_fault_t fault)
{
    const struct simctl_device_faults *f = record_of(faults, g);
    return (unsigned)fault < SIMCTL_FAULT_COUNT && f != NULL && f->active[fault];
}

uint64_t simctl_fault_since_us(const simctl_faults_t *faults, const gripper_t *g,
                               simctl_fault_t fault)
{
    return simctl_fault_active(faults, g, fault) ? record_of(faults, g)->since_us[fault] : 0u;
}
