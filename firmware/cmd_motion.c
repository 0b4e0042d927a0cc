/* Motion commands (manual 2.2.1-2.2.4, 3.2): validate, then hand the axis
 * a target. The motion supervisor (motion.c) reports how they end. */
#include "dispatch.h"
#include "hal_axis.h"
#include "hal_device.h"
#include "hal_log.h"
#include "motion.h"

/* Optional float argument i, or the default when it was not given. */
static wsg_status_t optional_float(const cmd_ctx_t *ctx, unsigned i, float fallback, float *out)
{
    if (ctx->cmd->argc <= i) {
        *out = fallback;
        return E_SUCCESS;
    }
    return arg_float(ctx, i, out);
}

static bool speed_ok(float speed)
{
    const hal_device_config_t *cfg = hal_device_config();
    return in_range(speed, cfg->speed_min_mm_s, cfg->speed_max_mm_s);
}

static float max_force(void)
{
    const hal_device_config_t *cfg = hal_device_config();
    return cfg->overdrive_mode && cfg->force_overdrive_n > 0.0f ? cfg->force_overdrive_n
                                                                : cfg->force_max_n;
}

/* The travel a target may have: the stroke, narrowed by soft limits. */
static bool target_ok(float target)
{
    const hal_device_config_t *cfg = hal_device_config();
    if (cfg->soft_limits_enabled) {
        return in_range(target, cfg->soft_limit_minus_mm, cfg->soft_limit_plus_mm);
    }
    return in_range(target, 0.0f, cfg->stroke_mm);
}

static float clamp_to_travel(float target)
{
    const hal_device_config_t *cfg = hal_device_config();
    float low = cfg->soft_limits_enabled ? cfg->soft_limit_minus_mm : 0.0f;
    float high = cfg->soft_limits_enabled ? cfg->soft_limit_plus_mm : cfg->stroke_mm;
    return target < low ? low : (target > high ? high : target);
}

static void start(cmd_ctx_t *ctx, wsg_motion_kind_t kind, float target, float speed, float force)
{
    wsg_device_t *dev = ctx->dev;
    /* manual 2.2.4: RELEASE follows a GRIP, and nothing else in between */
    dev->grip.release_permitted = kind == MOTION_GRIP;
    motion_begin(dev, ctx->session, kind);
    dev->motion.target_mm = target;
    dev->motion.speed_mm_s = speed;
    dev->motion.force_n = force;
    hal_axis_move(target, speed, hal_device_config()->default_accel_mm_s2, force);
    reply_ack(ctx);
}

wsg_status_t cmd_home(cmd_ctx_t *ctx)
{
    const hal_device_config_t *cfg = hal_device_config();
    bool positive = cfg->home_positive;
    if (ctx->cmd->argc == 1) {
        wsg_status_t status = arg_bool(ctx, 0, &positive);
        if (status != E_SUCCESS) {
            return status;
        }
    }
    wsg_status_t status = motion_check_allowed(ctx->dev, false);
    if (status != E_SUCCESS) {
        return status;
    }
    /* The position is unknown until the end stop is found: aim well beyond it. */
    float target = positive ? 3.0f * cfg->stroke_mm : -2.0f * cfg->stroke_mm;
    ctx->dev->referenced = false;
    flags_set(ctx->dev, SF_REFERENCED, false);
    grip_set_state(ctx->dev, GS_POSITIONING);
    start(ctx, MOTION_HOME, target, cfg->homing_speed_mm_s, HOMING_FORCE_FRACTION * max_force());
    return E_SUCCESS;
}

wsg_status_t cmd_move(cmd_ctx_t *ctx)
{
    const hal_device_config_t *cfg = hal_device_config();
    float target = 0.0f;
    float speed = 0.0f;
    wsg_status_t status = arg_float(ctx, 0, &target);
    if (status == E_SUCCESS) {
        status = optional_float(ctx, 1, cfg->default_speed_mm_s, &speed);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    if (!target_ok(target) || !speed_ok(speed)) {
        return E_RANGE_ERROR;
    }
    /* streaming clients send the next MOVE while one runs: it takes over */
    motion_supersede_move(ctx->dev);
    status = motion_check_allowed(ctx->dev, true);
    if (status != E_SUCCESS) {
        return status;
    }
    grip_set_state(ctx->dev, GS_POSITIONING);
    start(ctx, MOTION_MOVE, target, speed, cfg->default_force_n);
    return E_SUCCESS;
}

typedef struct {
    float force;
    bool has_width;
    float width;
    float speed;
} grip_args_t;

static wsg_status_t read_grip_args(const cmd_ctx_t *ctx, grip_args_t *a)
{
    const hal_device_config_t *cfg = hal_device_config();
    a->has_width = ctx->cmd->argc >= 2;
    wsg_status_t status = optional_float(ctx, 0, cfg->default_force_n, &a->force);
    if (status == E_SUCCESS) {
        status = optional_float(ctx, 1, 0.0f, &a->width);
    }
    if (status == E_SUCCESS) {
        status = optional_float(ctx, 2, cfg->default_speed_mm_s, &a->speed);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    if (!in_range(a->force, cfg->force_min_n, max_force()) || !speed_ok(a->speed) ||
        (a->has_width && !in_range(a->width, 0.0f, cfg->stroke_mm))) {
        return E_RANGE_ERROR;
    }
    return E_SUCCESS;
}

wsg_status_t cmd_grip(cmd_ctx_t *ctx)
{
    grip_args_t a;
    wsg_status_t status = read_grip_args(ctx, &a);
    if (status == E_SUCCESS) {
        status = motion_check_allowed(ctx->dev, true);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    wsg_device_t *dev = ctx->dev;
    if (dev->grip.state == GS_HOLDING) {
        return E_ACCESS_DENIED; /* manual 2.2.3: release first */
    }
    float clt = ctx->session->clt_mm;
    /* Inside grip closes on the part; with a width beyond the jaws, grip outside.
     * Without a width the jaws close until something stops them (manual 2.2.3:
     * they grip themselves), so aim past the closed position whatever the CLT. */
    int8_t direction = (a.has_width && a.width > dev->axis.position_mm) ? 1 : -1;
    float target = a.has_width ? a.width + (float)direction * clt : -hal_device_config()->stroke_mm;
    dev->grip.direction = direction;
    dev->grip.force_n = a.force;
    dev->grip.clt_mm = clt;
    dev->grip.stats[0]++;
    dev->motion.grip_has_width = a.has_width;
    dev->motion.grip_width_mm = a.width;
    dev->motion.grip_pwt_mm = ctx->session->pwt_mm;
    dev->motion.grip_clt_mm = clt;
    grip_set_state(dev, GS_GRASPING);
    start(ctx, MOTION_GRIP, target, a.speed, a.force);
    return E_SUCCESS;
}

wsg_status_t cmd_release(cmd_ctx_t *ctx)
{
    const hal_device_config_t *cfg = hal_device_config();
    float distance = 0.0f;
    float speed = 0.0f;
    wsg_status_t status = optional_float(ctx, 0, cfg->default_pullback_mm, &distance);
    if (status == E_SUCCESS) {
        status = optional_float(ctx, 1, cfg->default_speed_mm_s, &speed);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    if (!in_range(distance, 0.0f, cfg->stroke_mm) || !speed_ok(speed)) {
        return E_RANGE_ERROR;
    }
    wsg_device_t *dev = ctx->dev;
    status = motion_check_allowed(dev, true);
    if (status != E_SUCCESS) {
        return status;
    }
    if (!dev->grip.release_permitted) {
        return E_ACCESS_DENIED; /* manual 2.2.4: only after a GRIP */
    }
    float target = clamp_to_travel(dev->axis.position_mm - (float)dev->grip.direction * distance);
    grip_set_state(dev, GS_RELEASING);
    start(ctx, MOTION_RELEASE, target, speed, cfg->default_force_n);
    return E_SUCCESS;
}

/* The outcome of a grip (HOLDING, NO PART, PART LOST): STOP leaves it. */
static bool is_grip_result(wsg_grip_state_t state)
{
    return state == GS_HOLDING || state == GS_NO_PART || state == GS_PART_LOST;
}

/* Manual 3.2.1: STOP ends a movement, with the drive's maximum deceleration;
 * it does not end a grip: a held part stays clamped and HOLDING. */
wsg_status_t cmd_stop(cmd_ctx_t *ctx)
{
    wsg_device_t *dev = ctx->dev;
    reply_ack(ctx);
    /* a drive still leaning on a block (after ERR 29) lets go as well */
    bool halt = dev->motion.kind != MOTION_NONE || flags_get(dev, SF_MOVING) ||
                flags_get(dev, SF_BLOCKED_MINUS) || flags_get(dev, SF_BLOCKED_PLUS);
    motion_abort(dev, E_CMD_ABORTED);
    if (halt) {
        hal_axis_stop(true);
    }
    flags_set(dev, SF_AXIS_STOPPED, true);
    flags_set(dev, SF_BLOCKED_MINUS, false);
    flags_set(dev, SF_BLOCKED_PLUS, false);
    bool keep = flags_get(dev, SF_FAST_STOP) ||
                (dev->motion.kind == MOTION_NONE && is_grip_result(dev->grip.state));
    if (!keep) {
        grip_set_state(dev, GS_IDLE);
    }
    return E_SUCCESS;
}

wsg_status_t cmd_faststop(cmd_ctx_t *ctx)
{
    reply_ack(ctx);
    wsg_device_fast_stop(ctx->dev, "FASTSTOP command");
    return E_SUCCESS;
}

wsg_status_t cmd_fsack(cmd_ctx_t *ctx)
{
    wsg_device_t *dev = ctx->dev;
    if (flags_get(dev, SF_FAST_STOP)) {
        if (flags_severe_fault(dev)) {
            return E_ACCESS_DENIED;
        }
        flags_set(dev, SF_FAST_STOP, false);
        hal_log(HAL_LOG_INFO, "fast stop acknowledged");
    }
    if (dev->grip.state == GS_ERROR) {
        grip_set_state(dev, GS_IDLE);
    }
    reply_ack(ctx);
    return E_SUCCESS;
}
