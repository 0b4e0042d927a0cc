/* The device aggregate: power-on state, the control step and its deadline. */
#include <string.h>

#include "hal_axis.h"
#include "hal_log.h"
#include "motion.h"
#include "wsg_internal.h"

void wsg_device_init(wsg_device_t *dev)
{
    const wsg_device_hooks_t *hooks = dev->hooks;
    void *hooks_ctx = dev->hooks_ctx;
    const hal_can_t *can = dev->fbus.can;
    memset(dev, 0, sizeof(*dev));
    dev->hooks = hooks;
    dev->hooks_ctx = hooks_ctx;
    dev->grip.state = GS_IDLE;
    dev->grip.direction = -1;
    wsg_fingers_reset(&dev->fingers);
    finger_bus_init(&dev->fbus, can);
    flags_refresh(dev);
}

void wsg_device_set_hooks(wsg_device_t *dev, const wsg_device_hooks_t *hooks, void *ctx)
{
    dev->hooks = hooks;
    dev->hooks_ctx = ctx;
}

void wsg_device_step(wsg_device_t *dev)
{
    flags_refresh(dev);
    finger_bus_step(dev);
    motion_step(dev);
    grip_monitor_step(dev);
    motion_block_watch_step(dev);
    flags_refresh(dev);
    autosend_step(dev);
}

uint64_t wsg_device_next_deadline_us(const wsg_device_t *dev)
{
    uint32_t tick = IDLE_TICK_US;
    if (dev->motion.kind != MOTION_NONE || flags_get(dev, SF_MOVING)) {
        tick = MOTION_TICK_US;
    } else if (dev->grip.state == GS_HOLDING || flags_get(dev, SF_BLOCKED_MINUS) ||
               flags_get(dev, SF_BLOCKED_PLUS)) {
        tick = HOLD_TICK_US;
    }
    uint64_t next = dev->now_us + tick;
    uint64_t autosend = autosend_next_due_us(dev);
    uint64_t bus = finger_bus_next_deadline_us(&dev->fbus);
    next = bus < next ? bus : next;
    return autosend < next ? autosend : next;
}

void wsg_device_attach_can(wsg_device_t *dev, const hal_can_t *can)
{
    finger_bus_init(&dev->fbus, can);
}

void wsg_device_fast_stop(wsg_device_t *dev, const char *why)
{
    motion_abort(dev, E_CMD_ABORTED);
    hal_axis_disable(); /* manual 3.2.2: a held part is no longer clamped */
    flags_set(dev, SF_FAST_STOP, true);
    grip_set_state(dev, GS_ERROR);
    char storage[96];
    textbuf_t tb;
    textbuf_init(&tb, storage, sizeof(storage));
    textbuf_put_str(&tb, "FAST STOP: ");
    textbuf_put_str(&tb, why);
    hal_log(HAL_LOG_WARN, storage);
}
