/* The system state flag register (Appendix B): flags the core latches itself
 * plus flags derived from the newest hardware reading. */
#include "hal_axis.h"
#include "hal_clock.h"
#include "hal_device.h"
#include "hal_temp.h"
#include "wsg_internal.h"

#define MOVING_SPEED_MM_S 0.01f
#define LIMIT_WINDOW_MM 0.01f

void flags_set(wsg_device_t *dev, wsg_sysflag_t flag, bool on)
{
    uint32_t bit = WSG_FLAG(flag);
    if (on) {
        dev->latched_flags |= bit;
        dev->flags |= bit;
    } else {
        dev->latched_flags &= ~bit;
        dev->flags &= ~bit;
    }
}

bool flags_get(const wsg_device_t *dev, wsg_sysflag_t flag)
{
    return (dev->flags & WSG_FLAG(flag)) != 0u;
}

bool flags_severe_fault(const wsg_device_t *dev)
{
    return dev->axis.current_fault || dev->axis.power_fault ||
           dev->temperature_c >= hal_device_config()->temp_fault_c;
}

uint32_t flags_for_session(const wsg_device_t *dev, const wsg_session_t *s)
{
    uint32_t own = s->cmd_failed ? WSG_FLAG(SF_CMD_FAILURE) : 0u;
    return (dev->flags & ~WSG_FLAG(SF_CMD_FAILURE)) | own;
}

static uint32_t soft_limit_flags(const wsg_device_t *dev, const hal_device_config_t *cfg)
{
    uint32_t flags = 0;
    if (!cfg->soft_limits_enabled || !dev->referenced) {
        return 0;
    }
    if (dev->axis.position_mm <= cfg->soft_limit_minus_mm + LIMIT_WINDOW_MM) {
        flags |= WSG_FLAG(SF_SOFT_LIMIT_MINUS);
    }
    if (dev->axis.position_mm >= cfg->soft_limit_plus_mm - LIMIT_WINDOW_MM) {
        flags |= WSG_FLAG(SF_SOFT_LIMIT_PLUS);
    }
    return flags;
}

static uint32_t derived_flags(const wsg_device_t *dev)
{
    const hal_device_config_t *cfg = hal_device_config();
    const hal_axis_status_t *axis = &dev->axis;
    uint32_t flags = soft_limit_flags(dev, cfg);
    float speed = axis->velocity_mm_s < 0.0f ? -axis->velocity_mm_s : axis->velocity_mm_s;
    if (axis->profile_active || speed > MOVING_SPEED_MM_S) {
        flags |= WSG_FLAG(SF_MOVING);
    }
    if (cfg->overdrive_mode && cfg->force_overdrive_n > 0.0f) {
        flags |= WSG_FLAG(SF_OVERDRIVE_MODE);
    }
    if (wsg_fingers_force_control(&dev->fingers)) {
        flags |= WSG_FLAG(SF_FORCECNTL_MODE);
    }
    if (dev->temperature_c >= cfg->temp_warning_c) {
        flags |= WSG_FLAG(SF_TEMP_WARNING);
    }
    if (dev->temperature_c >= cfg->temp_fault_c) {
        flags |= WSG_FLAG(SF_TEMP_FAULT);
    }
    if (axis->power_fault) {
        flags |= WSG_FLAG(SF_POWER_FAULT);
    }
    if (axis->current_fault) {
        flags |= WSG_FLAG(SF_CURR_FAULT);
    }
    if (wsg_fingers_faulted(&dev->fingers)) {
        flags |= WSG_FLAG(SF_FINGER_FAULT);
    }
    return flags;
}

/* Reads the clock and the hardware, recomputes the register and raises a
 * FAST STOP on a severe fault (manual 3.2.3). */
void flags_refresh(wsg_device_t *dev)
{
    dev->now_us = hal_clock_now_us();
    hal_axis_status(&dev->axis);
    finger_bus_observe_axis(&dev->fbus, &dev->fingers, &dev->axis);
    dev->temperature_c = hal_temp_board_c();
    dev->flags = dev->latched_flags | derived_flags(dev);
    if (flags_severe_fault(dev) && !flags_get(dev, SF_FAST_STOP)) {
        wsg_device_fast_stop(dev, "severe fault (temperature, power or motor current)");
    }
}
