/* SPDX-License-Identifier: BSD-3-Clause */
/* The motion supervisor: watches the axis while HOME, MOVE, GRIP or RELEASE
 * runs and decides when it has finished, failed or been aborted; and grip
 * monitoring while a part is held. It is the only writer of the axis (the
 * finger bus's force loop hands it a force request). Completion goes to the
 * operation's owner as an event, never from the call that started the
 * operation: an operation that runs to its end is reported by the control
 * step; one that is ended (STOP, FAST STOP, a superseding MOVE) is reported
 * at once, inside the call that ends it, so that its final reply precedes
 * the reply to the command that ended it. */
#include "priv/motion_tuning.h"
#include "wsg/wsg_textbuf.h"
#include "priv/wsg_dev.h"

static float absf(float v)
{
    return v < 0.0f ? -v : v;
}

void wsg_grip_set_state(wsg_dev_t *dev, wsg_grip_state_t state)
{
    wsg_grip_state_t from = dev->grip.state;
    if (from == state) {
        return;
    }
    dev->grip.state = state;
    dev->grip.weak = false;
    for (const wsg_device_observer_t *o = dev->observers.device; o != NULL; o = o->next) {
        if (o->grip_state_changed != NULL) {
            o->grip_state_changed(o->ctx, from, state);
        }
    }
}

/* A time of the mechanics (wsg_mechanics_t): the configured one, or the
 * built-in one where the configuration leaves it 0. */
static uint64_t tuned_us(uint32_t configured_us, uint32_t built_in_us)
{
    return configured_us != 0u ? configured_us : built_in_us;
}

/* True once `condition` has held without a break for `duration_us`. */
static bool held_for(wsg_dev_t *dev, bool condition, uint64_t duration_us)
{
    dev_motion_t *m = &dev->motion;
    if (!condition) {
        m->condition_holding = false;
        return false;
    }
    if (!m->condition_holding) {
        m->condition_holding = true;
        m->condition_since_us = dev->sensed.now_us;
    }
    return dev->sensed.now_us - m->condition_since_us >= duration_us;
}

/* The operation's outcome is its owner's event; the device keeps it as
 * SF_CMD_FAILURE (the motion command's last word sets or clears it). */
static void finish(wsg_dev_t *dev, wsg_status_t status)
{
    dev_motion_t *m = &dev->motion;
    wsg_owner_t *owner = m->owner;
    wsg_op_t op = m->kind == WSG_MOTION_HOME   ? WSG_OP_HOME
                  : m->kind == WSG_MOTION_MOVE ? WSG_OP_MOVE
                  : m->kind == WSG_MOTION_GRIP ? WSG_OP_GRIP
                                               : WSG_OP_RELEASE;
    m->kind = WSG_MOTION_NONE;
    m->owner = NULL;
    wsg_flags_set(dev, SF_CMD_FAILURE, status != E_SUCCESS);
    if (owner != NULL) { /* else its connection has gone */
        owner->done(owner, op, status);
    }
}

void wsg_motion_drive(wsg_dev_t *dev, float target_mm, float speed_mm_s, float force_n)
{
    dev->axis_commanded = true;
    dev->hal.axis.ops->move(dev->hal.axis.ctx, target_mm, speed_mm_s, dev->cfg.default_accel_mm_s2,
                            force_n);
}

void wsg_motion_halt(wsg_dev_t *dev, bool fast)
{
    dev->axis_commanded = true;
    dev->hal.axis.ops->stop(dev->hal.axis.ctx, fast);
}

static void motion_disable(wsg_dev_t *dev)
{
    dev->axis_commanded = true;
    dev->hal.axis.ops->disable(dev->hal.axis.ctx);
}

/* The finger bus's force loop asks, the supervisor drives. */
void wsg_motion_apply_force_request(wsg_dev_t *dev)
{
    float limit = 0.0f;
    if (wsg_finger_bus_take_force_request(&dev->fbus, &limit)) {
        wsg_motion_drive(dev, dev->motion.target_mm, dev->motion.speed_mm_s, limit);
    }
}

wsg_status_t wsg_motion_check_allowed(wsg_dev_t *dev, bool needs_reference)
{
    if (wsg_flags_get(dev, SF_FAST_STOP)) {
        return E_ACCESS_DENIED;
    }
    if (dev->motion.kind != WSG_MOTION_NONE) {
        return E_ALREADY_RUNNING;
    }
    if (needs_reference && !dev->referenced) {
        return E_NOT_INITIALIZED;
    }
    return E_SUCCESS;
}

bool wsg_motion_supersede_move(wsg_dev_t *dev)
{
    const dev_motion_t *m = &dev->motion;
    if (m->kind != WSG_MOTION_MOVE || !dev->cfg.move_retarget) {
        return false;
    }
    finish(dev, E_CMD_ABORTED);
    return true;
}

void wsg_motion_begin(wsg_dev_t *dev, wsg_owner_t *owner, wsg_motion_kind_t kind)
{
    dev_motion_t *m = &dev->motion;
    dev->velocity.active = false; /* any motion takes the axis over */
    m->kind = kind;
    m->owner = owner;
    m->stop_on_block = false;
    m->started_us = dev->sensed.now_us;
    m->condition_holding = false;
    m->force_clear = dev->sensed.force_n < CONTACT_FORCE_N;
    m->contact_seen = false;
    m->home_released = false;
    m->block_clearing = false;
    wsg_flags_set(dev, SF_AXIS_STOPPED, false);
    wsg_flags_set(dev, SF_TARGET_POS_REACHED, false);
    wsg_flags_set(dev, SF_BLOCKED_MINUS, false);
    wsg_flags_set(dev, SF_BLOCKED_PLUS, false);
}

void wsg_motion_abort(wsg_dev_t *dev)
{
    if (dev->motion.kind != WSG_MOTION_NONE) {
        finish(dev, E_CMD_ABORTED);
    }
}

void wsg_motion_fast_stop(wsg_dev_t *dev, const char *why)
{
    wsg_motion_velocity_end(dev);
    motion_disable(dev); /* manual 3.2.2: a held part is no longer clamped */
    wsg_flags_set(dev, SF_FAST_STOP, true);
    wsg_grip_set_state(dev, GS_ERROR);
    char storage[128];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, "FAST STOP: ");
    wsg_textbuf_put_str(&tb, why);
    hal_log(HAL_LOG_WARN, storage);
    wsg_motion_abort(dev);
}

/* Ends a command on a blocked axis (ERR 29). The drive stays where it is,
 * leaning on the block with the command's force, so that it notices when the
 * block goes away (Appendix B); the flag stays latched until then, the next
 * motion command or STOP. */
static void fail_blocked(wsg_dev_t *dev, int8_t direction)
{
    const wsg_config_t *cfg = &dev->cfg;
    float hold_mm = dev->sensed.axis.position_mm + (float)direction * BLOCK_PRELOAD_MM;
    if (dev->motion.stop_on_block) {
        wsg_motion_halt(dev, false); /* binary pre-position: stop, do not lean */
    } else {
        wsg_motion_drive(dev, hold_mm, cfg->speed_min_mm_s, dev->motion.force_n);
    }
    wsg_flags_set(dev, direction < 0 ? SF_BLOCKED_MINUS : SF_BLOCKED_PLUS, true);
    wsg_grip_set_state(dev, GS_ERROR);
    finish(dev, E_AXIS_BLOCKED);
}

static void home_done(wsg_dev_t *dev)
{
    dev->referenced = true;
    wsg_flags_set(dev, SF_REFERENCED, true);
    wsg_flags_set(dev, SF_TARGET_POS_REACHED, true);
    wsg_grip_set_state(dev, GS_IDLE);
    hal_log(HAL_LOG_INFO, "homing done");
    finish(dev, E_SUCCESS);
}

/* Homing drives into the end stop until the drive has seen it blocked for
 * HOME_BLOCK_DETECT_US, takes the origin there and stops pushing; FIN waits
 * until the force reading has fallen (an FMF reports with a delay), so that
 * neither FORCE? nor the next GRIP sees the end stop's force. */
static void home_step(wsg_dev_t *dev)
{
    const wsg_config_t *cfg = &dev->cfg;
    dev_motion_t *m = &dev->motion;
    bool positive = m->target_mm > 0.0f;
    if (m->home_released) {
        bool settled = dev->sensed.force_n < CONTACT_FORCE_N;
        if (settled || dev->sensed.now_us - m->condition_since_us >= HOME_SETTLE_MAX_US) {
            home_done(dev);
        }
        return;
    }
    if (held_for(dev, dev->sensed.axis.blocked == (positive ? 1 : -1),
                 tuned_us(cfg->mechanics.home_block_detect_us, HOME_BLOCK_DETECT_US))) {
        dev->axis_commanded = true;
        dev->hal.axis.ops->set_position(dev->hal.axis.ctx, positive ? cfg->stroke_mm : 0.0f);
        wsg_motion_halt(dev, false);
        m->home_released = true;
        m->condition_since_us = dev->sensed.now_us;
    } else if (dev->sensed.now_us - m->started_us >= HOME_TIMEOUT_US) {
        wsg_motion_halt(dev, false);
        wsg_grip_set_state(dev, GS_ERROR);
        finish(dev, E_TIMEOUT);
    }
}

/* MOVE and RELEASE: reach the target or report the axis blocked. */
static void position_step(wsg_dev_t *dev)
{
    const hal_axis_status_t *axis = &dev->sensed.axis;
    if (axis->blocked != 0) {
        if (held_for(dev, true,
                     tuned_us(dev->cfg.mechanics.block_detect_us, BLOCKED_DEBOUNCE_US))) {
            fail_blocked(dev, axis->blocked);
        }
        return;
    }
    bool in_position = !axis->profile_active &&
                       absf(axis->position_mm - dev->motion.target_mm) <= POSITION_TOLERANCE_MM;
    if (held_for(dev, in_position, tuned_us(dev->cfg.mechanics.settle_us, SETTLE_US))) {
        wsg_flags_set(dev, SF_TARGET_POS_REACHED, true);
        wsg_grip_set_state(dev, GS_IDLE);
        finish(dev, E_SUCCESS);
    }
}

/* Where the jaws may travel to before "no part" is declared (manual 2.2.6):
 * clamping travel from the contact point if the part was met before the
 * nominal width, otherwise from the nominal width. */
float wsg_motion_grip_travel_limit(const dev_motion_t *m, int8_t direction)
{
    float from = m->grip_width_mm;
    if (m->contact_seen && (m->contact_mm - m->grip_width_mm) * (float)-direction > 0.0f) {
        from = m->contact_mm;
    }
    return from + (float)direction * m->grip_clt_mm;
}

static void grip_no_part(wsg_dev_t *dev)
{
    wsg_motion_halt(dev, false);
    dev->grip.stats[1]++;
    wsg_grip_set_state(dev, GS_NO_PART);
    finish(dev, E_CMD_FAILED);
}

/* Part detection counts a contact met in the grip's direction: the jaws are
 * blocked that way, or the force rose after the grip started (not a reading
 * left from homing or from leaning on a block behind them) while they move
 * that way. */
static bool new_contact(wsg_dev_t *dev, int8_t direction)
{
    dev_motion_t *m = &dev->motion;
    const hal_axis_status_t *axis = &dev->sensed.axis;
    if (dev->sensed.force_n < CONTACT_FORCE_N) {
        m->force_clear = true;
        return false;
    }
    bool rose_ahead = m->force_clear && axis->velocity_mm_s * (float)direction > 0.0f;
    return !m->contact_seen && (rose_ahead || axis->blocked == direction);
}

static void grip_step(wsg_dev_t *dev)
{
    dev_motion_t *m = &dev->motion;
    const hal_axis_status_t *axis = &dev->sensed.axis;
    int8_t direction = dev->grip.direction;
    if (new_contact(dev, direction)) {
        m->contact_seen = true;
        m->contact_mm = axis->position_mm;
        float early = (m->contact_mm - m->grip_width_mm) * (float)-direction;
        if (m->grip_has_width && early > m->grip_pwt_mm) {
            fail_blocked(dev, direction); /* collision before the tolerance band */
            return;
        }
    }
    if (held_for(dev, axis->blocked == direction,
                 tuned_us(dev->cfg.mechanics.settle_us, SETTLE_US))) {
        dev->grip.hold_mm = axis->position_mm;
        dev->grip.monitored = m->grip_has_width; /* manual 2.2.3: cases 3 and 4 only */
        wsg_grip_set_state(dev, GS_HOLDING);
        finish(dev, E_SUCCESS);
        return;
    }
    if (axis->blocked != 0) {
        return;
    }
    bool travel_used =
        m->grip_has_width &&
        (axis->position_mm - wsg_motion_grip_travel_limit(m, direction)) * (float)direction >=
            -POSITION_TOLERANCE_MM;
    if (travel_used || !axis->profile_active) {
        grip_no_part(dev);
    }
}

/* Soft limits (manual App. B SF_SOFT_LIMIT_±: "a further movement into this
 * direction is not allowed"; binary S1 §3.3.5): a motion heading on into a
 * soft-limit zone raises FAST STOP. Homing ignores them (manual 2.x). Targets
 * are checked against the limits already, so only a grip closing on no part
 * or a block giving way gets here. */
static bool runs_into_soft_limit(const wsg_dev_t *dev)
{
    const wsg_config_t *cfg = &dev->cfg;
    if (!cfg->soft_limits_enabled || !dev->referenced || dev->motion.kind == WSG_MOTION_HOME) {
        return false;
    }
    float x = dev->sensed.axis.position_mm;
    float v = dev->sensed.axis.velocity_mm_s;
    return (x < cfg->soft_limit_minus_mm - SOFT_LIMIT_MARGIN_MM && v < 0.0f) ||
           (x > cfg->soft_limit_plus_mm + SOFT_LIMIT_MARGIN_MM && v > 0.0f);
}

/* Velocity mode aims at a stroke end past the jaws' travel, so that they
 * push on whatever stops them with the force limit, or at the soft limit,
 * where they stop. Speed 0 holds where the jaws are. */
void wsg_motion_velocity_drive(wsg_dev_t *dev)
{
    const wsg_config_t *cfg = &dev->cfg;
    float v = dev->velocity.speed_mm_s;
    float force = dev->cfg.default_force_n;
    if (v == 0.0f) {
        wsg_motion_drive(dev, dev->sensed.axis.position_mm, cfg->speed_min_mm_s, force);
        return;
    }
    float target = v > 0.0f ? cfg->stroke_mm + VELOCITY_OVERTRAVEL_MM : -VELOCITY_OVERTRAVEL_MM;
    if (cfg->soft_limits_enabled) {
        target = v > 0.0f ? cfg->soft_limit_plus_mm : cfg->soft_limit_minus_mm;
    }
    wsg_motion_drive(dev, target, absf(v), force);
}

void wsg_motion_velocity_end(wsg_dev_t *dev)
{
    dev->velocity.active = false;
}

/* Velocity mode is not ended by a block: SF_BLOCKED_± show while the jaws
 * push on something, and clear when they move away. */
static void velocity_step(wsg_dev_t *dev)
{
    int8_t blocked = dev->sensed.axis.blocked;
    wsg_flags_set(dev, SF_BLOCKED_MINUS, blocked < 0);
    wsg_flags_set(dev, SF_BLOCKED_PLUS, blocked > 0);
}

void wsg_motion_step(wsg_dev_t *dev)
{
    dev_motion_t *m = &dev->motion;
    if (m->kind == WSG_MOTION_NONE) {
        if (dev->velocity.active) {
            velocity_step(dev);
        }
        return;
    }
    if (runs_into_soft_limit(dev)) {
        wsg_motion_fast_stop(dev, "soft limit reached");
        return;
    }
    switch (m->kind) {
    case WSG_MOTION_HOME:
        home_step(dev);
        break;
    case WSG_MOTION_MOVE:
    case WSG_MOTION_RELEASE:
        position_step(dev);
        break;
    case WSG_MOTION_GRIP:
        grip_step(dev);
        break;
    case WSG_MOTION_NONE:
    default:
        break;
    }
}

/* Grip monitoring (manual 2.2.3): a held part that gives way or vanishes
 * turns HOLDING into PART LOST. */
void wsg_grip_monitor_step(wsg_dev_t *dev)
{
    dev_grip_t *grip = &dev->grip;
    if (grip->state != GS_HOLDING || !grip->monitored || dev->motion.kind != WSG_MOTION_NONE) {
        return;
    }
    float moved_on = (dev->sensed.axis.position_mm - grip->hold_mm) * (float)grip->direction;
    bool weak =
        dev->sensed.force_n < LOST_FORCE_FRACTION * grip->force_n || moved_on > grip->clt_mm;
    if (!weak) {
        grip->weak = false;
        return;
    }
    if (!grip->weak) {
        grip->weak = true;
        grip->weak_since_us = dev->sensed.now_us;
    }
    if (dev->sensed.now_us - grip->weak_since_us >=
        tuned_us(dev->cfg.mechanics.part_lost_us, PART_LOST_DEBOUNCE_US)) {
        wsg_motion_halt(dev, false);
        grip->stats[2]++;
        wsg_grip_set_state(dev, GS_PART_LOST);
        hal_log(HAL_LOG_WARN, "part lost");
    }
}

/* Appendix B: SF_BLOCKED_± also clear once the blocking condition is gone,
 * i.e. the jaws no longer press on anything for BLOCKED_DEBOUNCE_US. */
void wsg_motion_block_watch_step(wsg_dev_t *dev)
{
    dev_motion_t *m = &dev->motion;
    bool latched = (dev->flags & (WSG_FLAG(SF_BLOCKED_MINUS) | WSG_FLAG(SF_BLOCKED_PLUS))) != 0u;
    if (!latched || m->kind != WSG_MOTION_NONE || dev->velocity.active ||
        dev->sensed.force_n >= CONTACT_FORCE_N) {
        m->block_clearing = false;
        return;
    }
    if (!m->block_clearing) {
        m->block_clearing = true;
        m->block_clearing_since_us = dev->sensed.now_us;
    }
    if (dev->sensed.now_us - m->block_clearing_since_us >= BLOCKED_DEBOUNCE_US) {
        m->block_clearing = false;
        wsg_motion_halt(dev, false);
        wsg_flags_set(dev, SF_BLOCKED_MINUS, false);
        wsg_flags_set(dev, SF_BLOCKED_PLUS, false);
        hal_log(HAL_LOG_INFO, "axis no longer blocked");
    }
}
