/* The motion supervisor: watches the axis while HOME, MOVE, GRIP or RELEASE
 * runs and decides when it has finished, failed or been aborted; and grip
 * monitoring while a part is held. Final replies are emitted only from the
 * control step, never in the same pass as the command's ACK. */
#include "hal_axis.h"
#include "hal_device.h"
#include "hal_log.h"
#include "motion.h"
#include "wsg_internal.h"

static float absf(float v)
{
    return v < 0.0f ? -v : v;
}

const char *motion_command_name(wsg_motion_kind_t kind)
{
    switch (kind) {
    case MOTION_HOME:
        return "HOME";
    case MOTION_MOVE:
        return "MOVE";
    case MOTION_GRIP:
        return "GRIP";
    case MOTION_RELEASE:
        return "RELEASE";
    case MOTION_NONE:
    default:
        return "";
    }
}

void grip_set_state(wsg_device_t *dev, wsg_grip_state_t state)
{
    wsg_grip_state_t from = dev->grip.state;
    if (from == state) {
        return;
    }
    dev->grip.state = state;
    dev->grip.weak = false;
    if (dev->hooks != NULL && dev->hooks->grip_state_changed != NULL) {
        dev->hooks->grip_state_changed(dev->hooks_ctx, from, state);
    }
}

/* True once `condition` has held without a break for `duration_us`. */
static bool held_for(wsg_device_t *dev, bool condition, uint64_t duration_us)
{
    wsg_motion_t *m = &dev->motion;
    if (!condition) {
        m->condition_holding = false;
        return false;
    }
    if (!m->condition_holding) {
        m->condition_holding = true;
        m->condition_since_us = dev->now_us;
    }
    return dev->now_us - m->condition_since_us >= duration_us;
}

static void finish(wsg_device_t *dev, wsg_status_t status)
{
    wsg_motion_t *m = &dev->motion;
    const char *name = motion_command_name(m->kind);
    wsg_session_t *owner = session_lookup(dev, m->owner_index, m->owner_generation);
    m->kind = MOTION_NONE;
    m->abort_requested = false;
    /* the motion command's outcome is its last word: it sets or clears the flag */
    flags_set(dev, SF_CMD_FAILURE, status != E_SUCCESS);
    if (owner == NULL) {
        return; /* the session that issued it has gone */
    }
    owner->cmd_failed = status != E_SUCCESS;
    if (status == E_SUCCESS) {
        session_send_word(dev, owner, "FIN", name);
    } else {
        session_send_error(dev, owner, name, status);
    }
}

/* A pending abort is reported before a new motion takes the axis over, so
 * STOP() followed at once by MOVE() works. */
wsg_status_t motion_check_allowed(wsg_device_t *dev, bool needs_reference)
{
    if (dev->motion.kind != MOTION_NONE && dev->motion.abort_requested) {
        finish(dev, dev->motion.abort_status);
    }
    if (flags_get(dev, SF_FAST_STOP)) {
        return E_ACCESS_DENIED;
    }
    if (dev->motion.kind != MOTION_NONE) {
        return E_ALREADY_RUNNING;
    }
    if (needs_reference && !dev->referenced) {
        return E_NOT_INITIALIZED;
    }
    return E_SUCCESS;
}

bool motion_supersede_move(wsg_device_t *dev)
{
    const wsg_motion_t *m = &dev->motion;
    if (m->kind != MOTION_MOVE || m->abort_requested || !hal_device_config()->move_retarget) {
        return false;
    }
    finish(dev, E_CMD_ABORTED);
    return true;
}

void motion_begin(wsg_device_t *dev, wsg_session_t *owner, wsg_motion_kind_t kind)
{
    wsg_motion_t *m = &dev->motion;
    m->kind = kind;
    m->owner_index = owner->index;
    m->owner_generation = owner->generation;
    m->started_us = dev->now_us;
    m->condition_holding = false;
    m->abort_requested = false;
    m->force_clear = dev->axis.force_n < CONTACT_FORCE_N;
    m->contact_seen = false;
    m->home_released = false;
    m->block_clearing = false;
    flags_set(dev, SF_AXIS_STOPPED, false);
    flags_set(dev, SF_TARGET_POS_REACHED, false);
    flags_set(dev, SF_BLOCKED_MINUS, false);
    flags_set(dev, SF_BLOCKED_PLUS, false);
}

void motion_abort(wsg_device_t *dev, wsg_status_t status)
{
    if (dev->motion.kind != MOTION_NONE && !dev->motion.abort_requested) {
        dev->motion.abort_requested = true;
        dev->motion.abort_status = status;
    }
}

/* Ends a command on a blocked axis (ERR 29). The drive stays where it is,
 * leaning on the block with the command's force, so that it notices when the
 * block goes away (Appendix B); the flag stays latched until then, the next
 * motion command or STOP. */
static void fail_blocked(wsg_device_t *dev, int8_t direction)
{
    const hal_device_config_t *cfg = hal_device_config();
    float hold_mm = dev->axis.position_mm + (float)direction * BLOCK_PRELOAD_MM;
    hal_axis_move(hold_mm, cfg->speed_min_mm_s, cfg->default_accel_mm_s2, dev->motion.force_n);
    flags_set(dev, direction < 0 ? SF_BLOCKED_MINUS : SF_BLOCKED_PLUS, true);
    grip_set_state(dev, GS_ERROR);
    finish(dev, E_AXIS_BLOCKED);
}

static void home_done(wsg_device_t *dev)
{
    dev->referenced = true;
    flags_set(dev, SF_REFERENCED, true);
    flags_set(dev, SF_TARGET_POS_REACHED, true);
    grip_set_state(dev, GS_IDLE);
    hal_log(HAL_LOG_INFO, "homing done");
    finish(dev, E_SUCCESS);
}

/* Homing drives into the end stop until the drive has seen it blocked for
 * HOME_BLOCK_DETECT_US, takes the origin there and stops pushing; FIN waits
 * until the force reading has fallen (an FMF reports with a delay), so that
 * neither FORCE? nor the next GRIP sees the end stop's force. */
static void home_step(wsg_device_t *dev)
{
    const hal_device_config_t *cfg = hal_device_config();
    wsg_motion_t *m = &dev->motion;
    bool positive = m->target_mm > 0.0f;
    if (m->home_released) {
        bool settled = dev->axis.force_n < CONTACT_FORCE_N;
        if (settled || dev->now_us - m->condition_since_us >= HOME_SETTLE_MAX_US) {
            home_done(dev);
        }
        return;
    }
    if (held_for(dev, dev->axis.blocked == (positive ? 1 : -1), HOME_BLOCK_DETECT_US)) {
        hal_axis_set_position(positive ? cfg->stroke_mm : 0.0f);
        hal_axis_stop(false);
        m->home_released = true;
        m->condition_since_us = dev->now_us;
    } else if (dev->now_us - m->started_us >= HOME_TIMEOUT_US) {
        hal_axis_stop(false);
        grip_set_state(dev, GS_ERROR);
        finish(dev, E_TIMEOUT);
    }
}

/* MOVE and RELEASE: reach the target or report the axis blocked. */
static void position_step(wsg_device_t *dev)
{
    const hal_axis_status_t *axis = &dev->axis;
    if (axis->blocked != 0) {
        if (held_for(dev, true, BLOCKED_DEBOUNCE_US)) {
            fail_blocked(dev, axis->blocked);
        }
        return;
    }
    bool in_position = !axis->profile_active &&
                       absf(axis->position_mm - dev->motion.target_mm) <= POSITION_TOLERANCE_MM;
    if (held_for(dev, in_position, SETTLE_US)) {
        flags_set(dev, SF_TARGET_POS_REACHED, true);
        grip_set_state(dev, GS_IDLE);
        finish(dev, E_SUCCESS);
    }
}

/* Where the jaws may travel to before "no part" is declared (manual 2.2.6):
 * clamping travel from the contact point if the part was met before the
 * nominal width, otherwise from the nominal width. */
static float grip_travel_limit(const wsg_motion_t *m, int8_t direction)
{
    float from = m->grip_width_mm;
    if (m->contact_seen && (m->contact_mm - m->grip_width_mm) * (float)-direction > 0.0f) {
        from = m->contact_mm;
    }
    return from + (float)direction * m->grip_clt_mm;
}

static void grip_no_part(wsg_device_t *dev)
{
    hal_axis_stop(false);
    dev->grip.stats[1]++;
    grip_set_state(dev, GS_NO_PART);
    finish(dev, E_CMD_FAILED);
}

/* Part detection counts a contact met in the grip's direction: the jaws are
 * blocked that way, or the force rose after the grip started (not a reading
 * left from homing or from leaning on a block behind them) while they move
 * that way. */
static bool new_contact(wsg_device_t *dev, int8_t direction)
{
    wsg_motion_t *m = &dev->motion;
    const hal_axis_status_t *axis = &dev->axis;
    if (axis->force_n < CONTACT_FORCE_N) {
        m->force_clear = true;
        return false;
    }
    bool rose_ahead = m->force_clear && axis->velocity_mm_s * (float)direction > 0.0f;
    return !m->contact_seen && (rose_ahead || axis->blocked == direction);
}

static void grip_step(wsg_device_t *dev)
{
    wsg_motion_t *m = &dev->motion;
    const hal_axis_status_t *axis = &dev->axis;
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
    if (held_for(dev, axis->blocked == direction, SETTLE_US)) {
        dev->grip.hold_mm = axis->position_mm;
        dev->grip.monitored = m->grip_has_width; /* manual 2.2.3: cases 3 and 4 only */
        grip_set_state(dev, GS_HOLDING);
        finish(dev, E_SUCCESS);
        return;
    }
    if (axis->blocked != 0) {
        return;
    }
    bool travel_used = m->grip_has_width &&
                       (axis->position_mm - grip_travel_limit(m, direction)) * (float)direction >=
                           -POSITION_TOLERANCE_MM;
    if (travel_used || !axis->profile_active) {
        grip_no_part(dev);
    }
}

void motion_step(wsg_device_t *dev)
{
    wsg_motion_t *m = &dev->motion;
    if (m->kind == MOTION_NONE) {
        return;
    }
    if (m->abort_requested) {
        finish(dev, m->abort_status);
        return;
    }
    switch (m->kind) {
    case MOTION_HOME:
        home_step(dev);
        break;
    case MOTION_MOVE:
    case MOTION_RELEASE:
        position_step(dev);
        break;
    case MOTION_GRIP:
        grip_step(dev);
        break;
    case MOTION_NONE:
    default:
        break;
    }
}

/* Grip monitoring (manual 2.2.3): a held part that gives way or vanishes
 * turns HOLDING into PART LOST. */
void grip_monitor_step(wsg_device_t *dev)
{
    wsg_grip_t *grip = &dev->grip;
    if (grip->state != GS_HOLDING || !grip->monitored || dev->motion.kind != MOTION_NONE) {
        return;
    }
    float moved_on = (dev->axis.position_mm - grip->hold_mm) * (float)grip->direction;
    bool weak = dev->axis.force_n < LOST_FORCE_FRACTION * grip->force_n || moved_on > grip->clt_mm;
    if (!weak) {
        grip->weak = false;
        return;
    }
    if (!grip->weak) {
        grip->weak = true;
        grip->weak_since_us = dev->now_us;
    }
    if (dev->now_us - grip->weak_since_us >= PART_LOST_DEBOUNCE_US) {
        hal_axis_stop(false);
        grip->stats[2]++;
        grip_set_state(dev, GS_PART_LOST);
        hal_log(HAL_LOG_WARN, "part lost");
    }
}

/* Appendix B: SF_BLOCKED_± also clear once the blocking condition is gone,
 * i.e. the jaws no longer press on anything for BLOCKED_DEBOUNCE_US. */
void motion_block_watch_step(wsg_device_t *dev)
{
    wsg_motion_t *m = &dev->motion;
    bool latched = flags_get(dev, SF_BLOCKED_MINUS) || flags_get(dev, SF_BLOCKED_PLUS);
    if (!latched || m->kind != MOTION_NONE || dev->axis.force_n >= CONTACT_FORCE_N) {
        m->block_clearing = false;
        return;
    }
    if (!m->block_clearing) {
        m->block_clearing = true;
        m->block_clearing_since_us = dev->now_us;
    }
    if (dev->now_us - m->block_clearing_since_us >= BLOCKED_DEBOUNCE_US) {
        m->block_clearing = false;
        hal_axis_stop(false);
        flags_set(dev, SF_BLOCKED_MINUS, false);
        flags_set(dev, SF_BLOCKED_PLUS, false);
        hal_log(HAL_LOG_INFO, "axis no longer blocked");
    }
}
