/* SPDX-License-Identifier: BSD-3-Clause */
#include "simctl_ops.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <strings.h>

#include "hal_clock.h"
#include "log.h"
#include "sim/sim_world.h"
#include "wsg/wsg_inject.h"

#define AMBIENT_MIN_C (-40.0)
#define AMBIENT_MAX_C 150.0
#define STIFFNESS_DEFAULT 100.0
#define PART_ARGUMENT_MAX 1e6
#define STEP_MAX_MS 3600000.0 /* one hour of simulated time per STEP */

void simctl_op_begin(gripper_t *g)
{
    wsg_sim_world_advance(&g->world, hal_clock_now_us());
    if (g->physics != NULL) {
        physics_world_advance(g->physics, hal_clock_now_us());
    }
}

void simctl_op_end(gripper_t *g)
{
    gripper_touch(g);
}

__attribute__((format(printf, 3, 4))) static bool refuse(simctl_op_t *op, wsg_status_t status,
                                                         const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(op->why, sizeof(op->why), fmt, ap);
    va_end(ap);
    op->status = status;
    return false;
}

/* Done: the reply "ACK NAME", or "NAME=value" with value. */
__attribute__((format(printf, 3, 4))) static bool done(simctl_op_t *op, const char *name,
                                                       const char *fmt, ...)
{
    op->status = E_SUCCESS;
    op->why[0] = '\0';
    if (fmt == NULL) {
        snprintf(op->reply, sizeof(op->reply), "ACK %s", name);
        return true;
    }
    char value[48];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(value, sizeof(value), fmt, ap);
    va_end(ap);
    snprintf(op->reply, sizeof(op->reply), "%s=%s", name, value);
    return true;
}

static bool checked(simctl_op_t *op)
{
    op->status = E_SUCCESS;
    op->why[0] = '\0';
    op->reply[0] = '\0';
    return true;
}

/* ---- the world around the jaws ---- */

static double stroke_mm(gripper_t *g)
{
    return (double)wsg_device_snapshot(&g->device)->config->stroke_mm;
}

/* A width strictly inside the stroke. */
static bool width_ok(gripper_t *g, double width, simctl_op_t *op)
{
    if (!(width > 0.0 && width < stroke_mm(g))) {
        return refuse(op, E_RANGE_ERROR, "width must be above 0 and below the %.0f mm stroke",
                      stroke_mm(g));
    }
    return true;
}

/* PART's optional argument number `argument` (counted from 1). */
static bool part_argument_ok(double value, unsigned argument, simctl_op_t *op)
{
    if (!(value >= 0.0 && value <= PART_ARGUMENT_MAX)) {
        return refuse(op, E_RANGE_ERROR, "argument %u must be 0 to 1000000", argument);
    }
    return true;
}

bool simctl_op_part(gripper_t *g, const simctl_part_args_t *args, bool only_check, simctl_op_t *op)
{
    const sim_part_t *now = &g->world.axis.part;
    double stiffness = args->stiffness_given ? args->stiffness_n_mm
                       : now->present        ? (double)now->stiffness_n_mm
                                             : STIFFNESS_DEFAULT;
    double slip = args->slip_given ? args->slip_force_n
                  : now->present   ? (double)now->slip_force_n
                                   : 0.0;
    if (!width_ok(g, args->width_mm, op) ||
        (args->stiffness_given && !part_argument_ok(stiffness, 2, op)) ||
        (args->slip_given && !part_argument_ok(slip, 3, op))) {
        return false;
    }
    if (only_check) {
        return checked(op);
    }
    wsg_sim_axis_set_part(&g->world.axis, (float)args->width_mm, (float)stiffness, (float)slip);
    host_logf(HAL_LOG_INFO, "world: part %.2f mm, %.1f N/mm, slips below %.1f N", args->width_mm,
              stiffness, slip);
    gripper_step_now(g);
    return done(op, "PART", NULL);
}

bool simctl_op_part_remove(gripper_t *g, simctl_op_t *op)
{
    if (!g->world.axis.part.present) {
        return refuse(op, E_NOT_AVAILABLE, "there is no part");
    }
    wsg_sim_axis_remove_part(&g->world.axis);
    host_logf(HAL_LOG_INFO, "world: part removed");
    gripper_step_now(g);
    return done(op, "PART_REMOVE", NULL);
}

bool simctl_op_part_slip(gripper_t *g, simctl_op_t *op)
{
    if (!g->world.axis.part.present) {
        return refuse(op, E_NOT_AVAILABLE, "there is no part");
    }
    wsg_sim_axis_slip_part(&g->world.axis);
    host_logf(HAL_LOG_INFO, "world: part slipped out of the jaws");
    gripper_step_now(g);
    return done(op, "PART_SLIP", NULL);
}

bool simctl_op_obstacle(gripper_t *g, double width_mm, bool only_check, simctl_op_t *op)
{
    if (!width_ok(g, width_mm, op)) {
        return false;
    }
    if (only_check) {
        return checked(op);
    }
    wsg_sim_axis_place_obstacle(&g->world.axis, (float)width_mm);
    host_logf(HAL_LOG_INFO, "world: obstacle at %.2f mm", width_mm);
    gripper_step_now(g);
    return done(op, "OBSTACLE", NULL);
}

bool simctl_op_obstacle_remove(gripper_t *g, simctl_op_t *op)
{
    if (!g->world.axis.obstacle.present) {
        return refuse(op, E_NOT_AVAILABLE, "there is no obstacle");
    }
    wsg_sim_axis_remove_obstacle(&g->world.axis);
    host_logf(HAL_LOG_INFO, "world: obstacle removed");
    gripper_step_now(g);
    return done(op, "OBSTACLE_REMOVE", NULL);
}

bool simctl_op_ambient(gripper_t *g, double celsius, bool only_check, simctl_op_t *op)
{
    if (!(celsius >= AMBIENT_MIN_C && celsius <= AMBIENT_MAX_C)) {
        return refuse(op, E_RANGE_ERROR, "ambient must be %g to %g C", AMBIENT_MIN_C,
                      AMBIENT_MAX_C);
    }
    if (only_check) {
        return checked(op);
    }
    wsg_sim_thermal_set_ambient(&g->world.thermal, (float)celsius);
    host_logf(HAL_LOG_INFO, "world: ambient %.1f C", celsius);
    return done(op, "AMBIENT", "%g", (double)g->world.thermal.ambient_c);
}

/* ---- injected faults ---- */

/* A hardware fault by its name and finger (an integer 0 or 1, for the
 * finger faults only) that device g can take (a finger fault needs its
 * finger bus). */
static bool device_fault(const gripper_t *g, const simctl_fault_args_t *args, simctl_fault_t *fault,
                         simctl_op_t *op)
{
    double finger = args->finger;
    if (args->finger_given && !(finger >= 0.0 && finger <= 1.0 && finger == floor(finger))) {
        return refuse(op, E_RANGE_ERROR, "the finger must be an integer 0 to 1");
    }
    if (args->finger_given && simctl_fault_by_name(args->name, -1, fault)) {
        return refuse(op, E_NO_PARAM_EXPECTED, "%s takes no finger", args->name);
    }
    if (!simctl_fault_by_name(args->name, args->finger_given ? (int)finger : -1, fault)) {
        return refuse(op, E_INVALID_PARAMETER,
                      "unknown fault %s (TEMP_WARNING, TEMP_FAULT, POWER, CURRENT, "
                      "FINGER_POWER|FINGER_INIT|FINGER_UNPLUG with finger 0 or 1)",
                      args->name);
    }
    if (!simctl_fault_possible(g, *fault)) {
        return refuse(op, E_FEATURE_NOT_SUPPORTED, "device %u has no finger bus (device 0 has)",
                      g->index);
    }
    return true;
}

bool simctl_op_fault(simctl_t *ctl, gripper_t *g, const simctl_fault_args_t *args, bool only_check,
                     simctl_op_t *op)
{
    simctl_fault_t fault;
    if (!device_fault(g, args, &fault, op)) {
        return false;
    }
    if (only_check) {
        return checked(op);
    }
    if (!simctl_fault_raise(simctl_faults(ctl), g, fault)) {
        return refuse(op, E_INSUFFICIENT_RESOURCES, "out of memory");
    }
    gripper_step_now(g);
    return done(op, "FAULT", NULL);
}

static void clear_failnext(gripper_t *g)
{
    wsg_device_t *dev = &g->device;
    const wsg_snapshot_t *snap = wsg_device_snapshot(dev);
    if (snap->injected_armed) {
        host_logf(HAL_LOG_INFO, "fault cleared: FAILNEXT %s", snap->injected_name);
        wsg_device_clear_injected_failure(dev);
    }
}

static void clear_delays(simctl_t *ctl, gripper_t *g)
{
    if (simctl_delay_clear_all(simctl_delays(ctl), &g->device, true) > 0) {
        host_logf(HAL_LOG_INFO, "fault cleared: DELAY (held lines delivered)");
    }
}

bool simctl_op_protocol_fault(const char *name)
{
    return strcasecmp(name, "DELAY") == 0 || strcasecmp(name, "FAILNEXT") == 0;
}

static bool clear_protocol(simctl_t *ctl, gripper_t *g, const simctl_fault_args_t *args,
                           bool only_check, simctl_op_t *op)
{
    if (args->finger_given) {
        return refuse(op, E_NO_PARAM_EXPECTED, "%s takes no finger", args->name);
    }
    if (only_check) {
        return checked(op);
    }
    if (strcasecmp(args->name, "DELAY") == 0) {
        clear_delays(ctl, g);
    } else {
        clear_failnext(g);
    }
    return done(op, "CLEAR", NULL);
}

bool simctl_op_clear(simctl_t *ctl, gripper_t *g, const simctl_fault_args_t *args, bool only_check,
                     simctl_op_t *op)
{
    simctl_fault_t fault;
    if (args->name == NULL) {
        if (only_check) {
            return checked(op);
        }
        simctl_fault_clear_all(simctl_faults(ctl), g);
        clear_delays(ctl, g);
        clear_failnext(g);
    } else if (simctl_op_protocol_fault(args->name)) {
        return clear_protocol(ctl, g, args, only_check, op);
    } else if (!device_fault(g, args, &fault, op)) {
        return false;
    } else if (only_check) {
        return checked(op);
    } else {
        simctl_fault_clear(simctl_faults(ctl), g, fault);
    }
    gripper_step_now(g);
    return done(op, "CLEAR", NULL);
}

/* ---- the one simulated clock ---- */

bool simctl_op_pause(simctl_t *ctl, simctl_op_t *op)
{
    simclock_t *clock = simctl_clock(ctl);
    if (!simclock_paused(clock)) {
        /* everything due up to now runs before time stops */
        simctl_tick(simctl_scheduler(ctl));
        simclock_pause(clock);
        host_logf(HAL_LOG_INFO, "clock paused");
    }
    return done(op, "PAUSE", NULL);
}

bool simctl_op_resume(simctl_t *ctl, simctl_op_t *op)
{
    simclock_t *clock = simctl_clock(ctl);
    if (simclock_paused(clock)) {
        simclock_resume(clock);
        host_logf(HAL_LOG_INFO, "clock resumed at %.3fx", simclock_scale(clock));
    }
    return done(op, "RESUME", NULL);
}

bool simctl_op_step(simctl_t *ctl, double ms, bool only_check, simctl_op_t *op)
{
    if (!(ms > 0.0 && ms <= STEP_MAX_MS)) {
        return refuse(op, E_RANGE_ERROR, "ms must be above 0 and at most %.0f", STEP_MAX_MS);
    }
    if (only_check) {
        return checked(op);
    }
    if (!simclock_paused(simctl_clock(ctl))) {
        return refuse(op, E_ACCESS_DENIED, "the clock is running; PAUSE() first");
    }
    simctl_run_watch(ctl)->active = false; /* the reply is STEP's, even if the last
                                            * run's never went out */
    simctl_step_begin(simctl_scheduler(ctl), (uint64_t)(ms * 1000.0 + 0.5));
    op->status = E_SUCCESS;
    op->why[0] = '\0';
    op->reply[0] = '\0'; /* when it has run: simctl_step_reply() */
    return true;
}

bool simctl_op_scale(simctl_t *ctl, double scale, bool only_check, simctl_op_t *op)
{
    if (!(scale >= SIMCLOCK_SCALE_MIN && scale <= SIMCLOCK_SCALE_MAX)) {
        return refuse(op, E_RANGE_ERROR, "the scale must be %g to %g", SIMCLOCK_SCALE_MIN,
                      SIMCLOCK_SCALE_MAX);
    }
    if (only_check) {
        return checked(op);
    }
    simctl_tick(simctl_scheduler(ctl));                 /* the old rate applies up to now */
    (void)simclock_set_scale(simctl_clock(ctl), scale); /* in range: checked above */
    simctl_reset_max_lag(simctl_scheduler(ctl));
    host_logf(HAL_LOG_INFO, "clock scale %.3fx", scale);
    return done(op, "SCALE", "%g", simclock_scale(simctl_clock(ctl)));
}
