/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's operations (wsg_device.h): typed, validated once, protocol
 * neutral. Range rules come from policy.c; the motion supervisor
 * (motion.c) reports how long operations end, to their owner. */
#include <string.h>

#include "hal_clock.h"
#include "priv/motion_tuning.h"
#include "priv/wsg_dev.h"

static void start(wsg_dev_t *dev, wsg_owner_t *owner, wsg_motion_kind_t kind, float target,
                  float speed, float force)
{
    /* manual 2.2.4: RELEASE follows a GRIP, and nothing else in between */
    dev->grip.release_permitted = kind == WSG_MOTION_GRIP;
    wsg_motion_begin(dev, owner, kind);
    dev->motion.target_mm = target;
    dev->motion.speed_mm_s = speed;
    dev->motion.force_n = force;
    wsg_motion_drive(dev, target, speed, force);
}

wsg_status_t wsg_op_home(wsg_device_t *device, wsg_owner_t *owner, const wsg_home_args_t *args)
{
    wsg_dev_t *dev = dev_of(device);
    const wsg_config_t *cfg = &dev->cfg;
    if ((unsigned)args->direction > WSG_HOME_NEGATIVE) {
        return E_INVALID_PARAMETER;
    }
    bool positive = args->direction == WSG_HOME_DEFAULT ? cfg->home_positive
                                                        : args->direction == WSG_HOME_POSITIVE;
    wsg_status_t status = wsg_motion_check_allowed(dev, false);
    if (status != E_SUCCESS) {
        return status;
    }
    /* The position is unknown until the end stop is found: aim well beyond it. */
    float target = positive ? 3.0f * cfg->stroke_mm : -2.0f * cfg->stroke_mm;
    dev->referenced = false;
    wsg_flags_set(dev, SF_REFERENCED, false);
    wsg_grip_set_state(dev, GS_POSITIONING);
    start(dev, owner, WSG_MOTION_HOME, target, cfg->homing_speed_mm_s,
          HOMING_FORCE_FRACTION * wsg_config_force_max(cfg));
    return E_SUCCESS;
}

wsg_status_t wsg_op_move(wsg_device_t *device, wsg_owner_t *owner, const wsg_move_args_t *args)
{
    wsg_dev_t *dev = dev_of(device);
    const wsg_config_t *cfg = &dev->cfg;
    float target = args->position_mm;
    if (args->relative) {
        target += dev->sensed.axis.position_mm;
    }
    if (!wsg_config_target_ok(cfg, target) || !wsg_config_speed_ok(cfg, args->speed_mm_s)) {
        return E_RANGE_ERROR;
    }
    /* streaming clients send the next MOVE while one runs: it takes over */
    wsg_motion_supersede_move(dev);
    wsg_status_t status = wsg_motion_check_allowed(dev, true);
    if (status != E_SUCCESS) {
        return status;
    }
    wsg_grip_set_state(dev, GS_POSITIONING);
    start(dev, owner, WSG_MOTION_MOVE, target, args->speed_mm_s, cfg->default_force_n);
    dev->motion.stop_on_block = args->stop_on_block;
    return E_SUCCESS;
}

static wsg_status_t check_grip(const wsg_config_t *cfg, const wsg_grip_args_t *args)
{
    bool ok = wsg_config_force_ok(cfg, args->force_n) &&
              wsg_config_speed_ok(cfg, args->speed_mm_s) &&
              (!args->has_width || wsg_config_length_ok(cfg, args->width_mm));
    return ok ? E_SUCCESS : E_RANGE_ERROR;
}

wsg_status_t wsg_op_grip(wsg_device_t *device, wsg_owner_t *owner, const wsg_grip_args_t *args)
{
    wsg_dev_t *dev = dev_of(device);
    wsg_status_t status = check_grip(&dev->cfg, args);
    if (status == E_SUCCESS) {
        status = wsg_motion_check_allowed(dev, true);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    if (dev->grip.state == GS_HOLDING) {
        return E_ACCESS_DENIED; /* manual 2.2.3: release first */
    }
    float clt = args->clt_mm;
    /* Inside grip closes on the part; with a width beyond the jaws, grip outside.
     * Without a width the jaws close until something stops them (manual 2.2.3:
     * they grip themselves), so aim past the closed position whatever the CLT. */
    int8_t direction = (args->has_width && args->width_mm > dev->sensed.axis.position_mm) ? 1 : -1;
    float target = args->has_width ? args->width_mm + (float)direction * clt : -dev->cfg.stroke_mm;
    dev->grip.direction = direction;
    dev->grip.force_n = args->force_n;
    dev->grip.clt_mm = clt;
    dev->grip.stats[0]++;
    dev->motion.grip_has_width = args->has_width;
    dev->motion.grip_width_mm = args->has_width ? args->width_mm : 0.0f;
    dev->motion.grip_pwt_mm = args->pwt_mm;
    dev->motion.grip_clt_mm = clt;
    wsg_grip_set_state(dev, GS_GRASPING);
    start(dev, owner, WSG_MOTION_GRIP, target, args->speed_mm_s, args->force_n);
    return E_SUCCESS;
}

static float clamp_to_travel(const wsg_config_t *cfg, float target)
{
    float low = 0.0f;
    float high = 0.0f;
    wsg_config_travel(cfg, &low, &high);
    return target < low ? low : (target > high ? high : target);
}

wsg_status_t wsg_op_release(wsg_device_t *device, wsg_owner_t *owner,
                            const wsg_release_args_t *args)
{
    wsg_dev_t *dev = dev_of(device);
    const wsg_config_t *cfg = &dev->cfg;
    bool range_ok = args->to_width ? wsg_config_target_ok(cfg, args->width_mm)
                                   : wsg_config_length_ok(cfg, args->distance_mm);
    if (!range_ok || !wsg_config_speed_ok(cfg, args->speed_mm_s)) {
        return E_RANGE_ERROR;
    }
    wsg_status_t status = wsg_motion_check_allowed(dev, true);
    if (status != E_SUCCESS) {
        return status;
    }
    if (!dev->grip.release_permitted) {
        return E_ACCESS_DENIED; /* manual 2.2.4: only after a GRIP */
    }
    float away = dev->sensed.axis.position_mm - (float)dev->grip.direction * args->distance_mm;
    float target = args->to_width ? args->width_mm : clamp_to_travel(cfg, away);
    wsg_grip_set_state(dev, GS_RELEASING);
    start(dev, owner, WSG_MOTION_RELEASE, target, args->speed_mm_s, cfg->default_force_n);
    return E_SUCCESS;
}

wsg_status_t wsg_op_velocity(wsg_device_t *device, float speed_mm_s)
{
    wsg_dev_t *dev = dev_of(device);
    const wsg_config_t *cfg = &dev->cfg;
    if (speed_mm_s != speed_mm_s) {
        return E_INVALID_PARAMETER; /* NaN */
    }
    /* A move replaces velocity mode, and velocity mode a running MOVE:
     * wsg50-ros-pkg's script sends its speed goal right after a position
     * goal, without stopping first (docs/scripting.md). */
    wsg_motion_supersede_move(dev);
    wsg_status_t status = wsg_motion_check_allowed(dev, true);
    if (status != E_SUCCESS) {
        return status;
    }
    float v = speed_mm_s > cfg->speed_max_mm_s    ? cfg->speed_max_mm_s
              : speed_mm_s < -cfg->speed_max_mm_s ? -cfg->speed_max_mm_s
                                                  : speed_mm_s;
    if (!dev->velocity.active) {
        dev->grip.release_permitted = false;
        wsg_grip_set_state(dev, GS_IDLE); /* no grip: nothing to monitor */
        wsg_flags_set(dev, SF_AXIS_STOPPED, false);
        wsg_flags_set(dev, SF_TARGET_POS_REACHED, false);
    }
    dev->velocity.active = true;
    dev->velocity.speed_mm_s = v;
    wsg_motion_velocity_drive(dev);
    return E_SUCCESS;
}

bool wsg_device_velocity_mode(const wsg_device_t *device, float *speed_mm_s)
{
    const dev_velocity_t *v = &dev_of_const(device)->velocity;
    if (speed_mm_s != NULL) {
        *speed_mm_s = v->active ? v->speed_mm_s : 0.0f;
    }
    return v->active;
}

/* The outcome of a grip (HOLDING, NO PART, PART LOST): STOP leaves it. */
static bool is_grip_result(wsg_grip_state_t state)
{
    return state == GS_HOLDING || state == GS_NO_PART || state == GS_PART_LOST;
}

/* The stopped motion ends here, before the op returns: its owner hears
 * E_CMD_ABORTED before the driver answers the STOP (docs/behaviour.md). */
wsg_status_t wsg_op_stop(wsg_device_t *device)
{
    wsg_dev_t *dev = dev_of(device);
    bool running = dev->motion.kind != WSG_MOTION_NONE;
    /* a drive still leaning on a block (after ERR 29) lets go as well */
    bool halt = running || wsg_flags_get(dev, SF_MOVING) || dev->velocity.active ||
                wsg_flags_get(dev, SF_BLOCKED_MINUS) || wsg_flags_get(dev, SF_BLOCKED_PLUS);
    wsg_motion_velocity_end(dev);
    if (halt) {
        wsg_motion_halt(dev, true);
    }
    wsg_flags_set(dev, SF_AXIS_STOPPED, true);
    wsg_flags_set(dev, SF_BLOCKED_MINUS, false);
    wsg_flags_set(dev, SF_BLOCKED_PLUS, false);
    bool keep = wsg_flags_get(dev, SF_FAST_STOP) || (!running && is_grip_result(dev->grip.state));
    if (!keep) {
        wsg_grip_set_state(dev, GS_IDLE);
    }
    wsg_motion_abort(dev);
    return E_SUCCESS;
}

wsg_status_t wsg_op_fast_stop(wsg_device_t *device, const char *why)
{
    wsg_motion_fast_stop(dev_of(device), why);
    return E_SUCCESS;
}

wsg_status_t wsg_op_fsack(wsg_device_t *device)
{
    wsg_dev_t *dev = dev_of(device);
    if (wsg_flags_get(dev, SF_FAST_STOP)) {
        if (wsg_flags_severe_fault(dev)) {
            return E_ACCESS_DENIED;
        }
        wsg_flags_set(dev, SF_FAST_STOP, false);
        hal_log(HAL_LOG_INFO, "fast stop acknowledged");
    }
    if (dev->grip.state == GS_ERROR) {
        wsg_grip_set_state(dev, GS_IDLE);
    }
    return E_SUCCESS;
}

wsg_status_t wsg_op_tare(wsg_device_t *device, int finger)
{
    wsg_dev_t *dev = dev_of(device);
    if (finger < -1 || finger >= WSG_FINGER_COUNT) {
        return E_INDEX_OUT_OF_BOUNDS;
    }
    return wsg_finger_bus_tare(&dev->fbus, &dev->fingers, finger);
}

wsg_status_t wsg_op_reset_grip_stats(wsg_device_t *device)
{
    memset(dev_of(device)->grip.stats, 0, sizeof(dev_of(device)->grip.stats));
    return E_SUCCESS;
}

/* A soft limit is set, then the configuration checked as a whole (the
 * minus limit below the plus one, both within the stroke); refused, it
 * keeps its value. */
static wsg_status_t set_soft_limit(wsg_config_t *cfg, wsg_setting_t which, float value)
{
    float before = wsg_config_setting_get(cfg, which);
    const char *why = NULL;
    wsg_config_setting_put(cfg, which, value);
    if (!wsg_config_check(cfg, &why)) {
        wsg_config_setting_put(cfg, which, before);
        return E_RANGE_ERROR;
    }
    return E_SUCCESS;
}

static bool value_ok(const wsg_config_t *cfg, wsg_setting_check_t check, float value)
{
    switch (check) {
    case WSG_SETTING_ACCEL:
        return wsg_config_accel_ok(cfg, value);
    case WSG_SETTING_FORCE:
        return wsg_config_force_ok(cfg, value);
    case WSG_SETTING_SPEED:
        return wsg_config_speed_ok(cfg, value);
    case WSG_SETTING_LENGTH:
        return wsg_config_length_ok(cfg, value);
    case WSG_SETTING_SWITCH:
    case WSG_SETTING_SOFT_LIMIT:
    default:
        return true;
    }
}

/* Checked and set as the settings table (settings.c) describes. */
wsg_status_t wsg_config_setting_set(wsg_config_t *cfg, wsg_setting_t which, float value)
{
    const wsg_setting_info_t *s = wsg_setting_info(which);
    if (s == NULL) {
        return E_INVALID_PARAMETER;
    }
    if (which == WSG_SET_OVERDRIVE && value != 0.0f && cfg->force_overdrive_n <= 0.0f) {
        return E_FEATURE_NOT_SUPPORTED;
    }
    if (s->check == WSG_SETTING_SOFT_LIMIT) {
        return set_soft_limit(cfg, which, value);
    }
    if (!value_ok(cfg, s->check, value)) {
        return E_RANGE_ERROR;
    }
    wsg_config_setting_put(cfg, which, value);
    return E_SUCCESS;
}

wsg_status_t wsg_op_set(wsg_device_t *device, wsg_setting_t which, float value)
{
    wsg_dev_t *dev = dev_of(device);
    wsg_status_t status = wsg_config_setting_set(&dev->cfg, which, value);
    if (status == E_SUCCESS && which == WSG_SET_FORCE_LIMIT && dev->velocity.active) {
        wsg_motion_velocity_drive(dev); /* the new limit applies at once */
    }
    return status;
}

/* Validated here, once, for GCL, the binary protocol and the web page
 * (docs/behaviour.md "Settings are validated in the core"). */
wsg_status_t wsg_config_set_tag(wsg_config_t *cfg, const char *tag, size_t len)
{
    if (len >= sizeof(cfg->tag)) {
        return E_RANGE_ERROR;
    }
    for (size_t i = 0; i < len; i++) {
        if (!wsg_config_text_char_ok(tag[i])) {
            return E_INVALID_PARAMETER;
        }
    }
    memcpy(cfg->tag, tag, len);
    cfg->tag[len] = '\0';
    return E_SUCCESS;
}

wsg_status_t wsg_op_set_tag(wsg_device_t *device, const char *tag, size_t len)
{
    return wsg_config_set_tag(&dev_of(device)->cfg, tag, len);
}

void wsg_device_sense(wsg_device_t *device)
{
    wsg_sense_and_react(dev_of(device));
}

void wsg_device_sense_if_moved_on(wsg_device_t *device)
{
    wsg_dev_t *dev = dev_of(device);
    if (dev->sense_reacted || hal_clock_now_us() != dev->sensed.now_us) {
        wsg_sense_and_react(dev);
    }
}
