/* SPDX-License-Identifier: BSD-3-Clause */
/* The device aggregate: init and reset, the control step, its deadline,
 * observers, fault injection and the snapshot. */
#include <string.h>

#include "priv/wsg_dev.h"
#include "wsg/wsg_inject.h"

static void power_on(wsg_dev_t *dev, const wsg_config_t *cfg)
{
    memset(&dev->motion, 0, sizeof(dev->motion));
    memset(&dev->grip, 0, sizeof(dev->grip));
    memset(&dev->velocity, 0, sizeof(dev->velocity));
    memset(&dev->script, 0, sizeof(dev->script)); /* a power cycle ends the script */
    memset(&dev->injected_failure, 0, sizeof(dev->injected_failure));
    dev->cfg = *cfg;
    dev->pace.rng = cfg->timing.seed; /* a power-on draws the same jitter again */
    dev->pace.free_at_us = 0;
    dev->grip.state = GS_IDLE;
    dev->grip.direction = -1;
    dev->referenced = false;
    dev->latched_flags = 0;
    dev->flags = 0;
    wsg_fingers_reset(&dev->fingers);
    wsg_finger_bus_init(&dev->fbus, dev->hal.can.ops != NULL ? &dev->hal.can : NULL);
    dev->fingers_unsensed = true;
    wsg_sense(dev);
}

void wsg_device_init(wsg_device_t *device, const wsg_config_t *cfg, const wsg_hal_t *hal)
{
    wsg_dev_t *dev = dev_of(device);
    memset(dev, 0, sizeof(*dev));
    dev->hal = *hal;
    wsg_timer_queue_init(&dev->timers);
    power_on(dev, cfg);
}

void wsg_device_reset(wsg_device_t *device, const wsg_config_t *cfg)
{
    wsg_dev_t *dev = dev_of(device);
    power_on(dev, cfg);
}

void wsg_device_add_observer(wsg_device_t *device, wsg_device_observer_t *node)
{
    wsg_device_observer_t **at = &dev_of(device)->observers.device;
    while (*at != NULL && *at != node) {
        at = &(*at)->next;
    }
    if (*at == NULL) {
        node->next = NULL;
        *at = node;
    }
}

void wsg_device_remove_observer(wsg_device_t *device, wsg_device_observer_t *node)
{
    wsg_device_observer_t **at = &dev_of(device)->observers.device;
    while (*at != NULL && *at != node) {
        at = &(*at)->next;
    }
    if (*at != NULL) {
        *at = node->next;
        node->next = NULL;
    }
}

void wsg_device_take_observers(wsg_device_t *device, wsg_device_observers_t *taken)
{
    wsg_dev_t *dev = dev_of(device);
    *taken = dev->observers;
    dev->observers = (wsg_device_observers_t){NULL, NULL, NULL, 0};
}

void wsg_device_give_observers(wsg_device_t *device, const wsg_device_observers_t *taken)
{
    dev_of(device)->observers = *taken;
}

/* Without a CAN handle the bus has nothing to do: its input is not built,
 * and it raises no force request (only its step does). */
static void step_finger_bus(wsg_dev_t *dev)
{
    dev->fingers_stepped = false;
    if (dev->fbus.can == NULL) {
        return;
    }
    bool holding = dev->grip.state == GS_HOLDING && dev->motion.kind == WSG_MOTION_NONE;
    wsg_finger_bus_follow_force(&dev->fbus, dev->sensed.axis.force_n);
    if (wsg_finger_bus_skip_step(&dev->fbus, &dev->fingers, dev->sensed.now_us, holding)) {
        return; /* a quiet step: no input to build */
    }
    dev->fingers_stepped = wsg_finger_bus_step(
        &dev->fbus, &dev->fingers,
        &(fbus_input_t){
            .now_us = dev->sensed.now_us,
            .position_mm = dev->sensed.axis.position_mm,
            .motor_force_n = dev->sensed.axis.force_n,
            .grip_state = (uint8_t)dev->grip.state,
            .holding = dev->grip.state == GS_HOLDING && dev->motion.kind == WSG_MOTION_NONE,
            .grip_force_n = dev->grip.force_n,
            .force_max_n = wsg_config_force_max(&dev->cfg),
        });
    if (dev->fingers_stepped) { /* only a full bus step raises a force request */
        dev->fingers_unsensed = true;
        wsg_motion_apply_force_request(dev);
    }
}

void wsg_device_step(wsg_device_t *device)
{
    wsg_dev_t *dev = dev_of(device);
    wsg_step_sense_and_react(dev);
    step_finger_bus(dev);
    wsg_motion_step(dev);
    wsg_grip_monitor_step(dev);
    wsg_motion_block_watch_step(dev);
    wsg_step_sense_and_react_if_changed(dev); /* what the step changed, for the timers below */
    if (wsg_timer_next_due(&dev->timers) <= dev->sensed.now_us) {
        wsg_timer_run_due(&dev->timers, dev->sensed.now_us);
    }
    dev->tick_from_us = dev->sensed.now_us; /* the senses above leave it to here */
}

uint64_t wsg_device_next_deadline_us(const wsg_device_t *device)
{
    const wsg_dev_t *dev = dev_of_const(device);
    uint32_t tick = wsg_device_tick_us(dev);
    uint64_t next = tick != 0u ? dev->tick_from_us + tick : UINT64_MAX;
    uint64_t timers = wsg_timer_next_due(&dev->timers);
    uint64_t bus = dev->fbus.can != NULL ? wsg_finger_bus_next_deadline_us(&dev->fbus) : UINT64_MAX;
    next = bus < next ? bus : next;
    return timers < next ? timers : next;
}

void wsg_device_inject_failure(wsg_device_t *device, const char *name, wsg_status_t status)
{
    dev_injected_failure_t *f = &dev_of(device)->injected_failure;
    strncpy(f->name, name, sizeof(f->name) - 1);
    f->name[sizeof(f->name) - 1] = '\0';
    f->status = status;
    f->armed = true;
}

void wsg_device_clear_injected_failure(wsg_device_t *device)
{
    dev_of(device)->injected_failure.armed = false;
}

bool wsg_device_take_injected_failure(wsg_device_t *device, const char *name, wsg_status_t *status)
{
    dev_injected_failure_t *f = &dev_of(device)->injected_failure;
    if (!f->armed || strcmp(f->name, name) != 0) {
        return false;
    }
    f->armed = false;
    *status = f->status;
    hal_log(HAL_LOG_WARN, "injected failure answered");
    return true;
}

void wsg_device_note_result(wsg_device_t *device, wsg_status_t status)
{
    wsg_flags_set(dev_of(device), SF_CMD_FAILURE, status != E_SUCCESS);
}

uint64_t wsg_device_next_conn_id(wsg_device_t *device)
{
    return ++dev_of(device)->next_conn_id;
}

void wsg_device_detach(wsg_device_t *device, const wsg_owner_t *owner)
{
    wsg_dev_t *dev = dev_of(device);
    if (owner != NULL && dev->motion.owner == owner) {
        dev->motion.owner = NULL; /* the motion runs on; its end has no receiver */
    }
}

bool wsg_device_owns_motion(const wsg_device_t *device, const wsg_owner_t *owner)
{
    const wsg_dev_t *dev = dev_of_const(device);
    return dev->motion.kind != WSG_MOTION_NONE && owner != NULL && dev->motion.owner == owner;
}
