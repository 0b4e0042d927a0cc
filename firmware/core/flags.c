/* SPDX-License-Identifier: BSD-3-Clause */
/* The system state flag register (Appendix B): flags the core latches itself
 * plus flags derived from the sensed readings. Pure: reads no hardware. */
#include "priv/wsg_dev.h"

#define MOVING_SPEED_MM_S 0.01f

void wsg_flags_set(wsg_dev_t *dev, wsg_sysflag_t flag, bool on)
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

static uint32_t soft_limit_flags(const wsg_dev_t *dev)
{
    const wsg_config_t *cfg = &dev->cfg;
    uint32_t flags = 0;
    if (!cfg->soft_limits_enabled || !dev->sensed.referenced) {
        return 0;
    }
    float position = dev->sensed.axis.position_mm;
    if (position <= cfg->soft_limit_minus_mm + LIMIT_WINDOW_MM) {
        flags |= WSG_FLAG(SF_SOFT_LIMIT_MINUS);
    }
    if (position >= cfg->soft_limit_plus_mm - LIMIT_WINDOW_MM) {
        flags |= WSG_FLAG(SF_SOFT_LIMIT_PLUS);
    }
    return flags;
}

static uint32_t derived_flags(const wsg_dev_t *dev)
{
    const wsg_config_t *cfg = &dev->cfg;
    const hal_axis_status_t *axis = &dev->sensed.axis;
    float temperature = dev->sensed.temperature_c;
    uint32_t flags = soft_limit_flags(dev);
    /* |v| > limit, without forming |v| (the same outcome for every v, NaN included) */
    float velocity = axis->velocity_mm_s;
    if (axis->profile_active || velocity > MOVING_SPEED_MM_S || velocity < -MOVING_SPEED_MM_S) {
        flags |= WSG_FLAG(SF_MOVING);
    }
    if (cfg->overdrive_mode && cfg->force_overdrive_n > 0.0f) {
        flags |= WSG_FLAG(SF_OVERDRIVE_MODE);
    }
    if (dev->sensed.force_control) {
        flags |= WSG_FLAG(SF_FORCECNTL_MODE);
    }
    if (temperature >= cfg->temp_warning_c) {
        flags |= WSG_FLAG(SF_TEMP_WARNING);
    }
    if (temperature >= cfg->temp_fault_c) {
        flags |= WSG_FLAG(SF_TEMP_FAULT);
    }
    if (axis->power_fault) {
        flags |= WSG_FLAG(SF_POWER_FAULT);
    }
    if (axis->current_fault) {
        flags |= WSG_FLAG(SF_CURR_FAULT);
    }
    if (dev->sensed.finger_faulted) {
        flags |= WSG_FLAG(SF_FINGER_FAULT);
    }
    return flags;
}

void wsg_flags_derive(wsg_dev_t *dev)
{
    dev->flags = dev->latched_flags | derived_flags(dev);
}

void wsg_script_set_flags(wsg_device_t *device, bool running, bool failure)
{
    wsg_dev_t *dev = dev_of(device);
    wsg_flags_set(dev, SF_SCRIPT_RUNNING, running);
    wsg_flags_set(dev, SF_SCRIPT_FAILURE, failure);
}
