/* SPDX-License-Identifier: BSD-3-Clause */
/* Control line -> command -> handler -> reply line. */
#include "commands.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands_internal.h"
#include "fleet.h"
#include "hal_clock.h"
#include "scheduler.h"
#include "sim/sim_world.h"

#define CALL GCL_FORM_CALL
#define QUERY GCL_FORM_QUERY
#define SET GCL_FORM_SET

static wsg_status_t help(simctl_ctx_t *ctx);

static const simctl_entry_t table[] = {
    {"PAUSE", CALL, 0, 0, sc_pause, "PAUSE()", true},
    {"RESUME", CALL, 0, 0, sc_resume, "RESUME()", true},
    {"STEP", CALL, 1, 1, sc_step, "STEP(ms)", false},
    {"RUN_UNTIL_DONE", CALL, 1, 1, sc_run_until_done, "RUN_UNTIL_DONE(max_ms)", false},
    {"SCALE", SET | QUERY, 0, 0, sc_scale, "SCALE=factor | SCALE?", true},
    {"SIMTIME", QUERY, 0, 0, sc_simtime, "SIMTIME?", true},
    {"TIMING", CALL | SET | QUERY, 0, 1, sc_timing, "TIMING=profile | TIMING(\"path\") | TIMING?",
     true},
    {"PART", CALL | QUERY, 1, 3, sc_part, "PART(width[,stiffness[,slip_force]]) | PART?", true},
    {"PART_REMOVE", CALL, 0, 0, sc_part_remove, "PART_REMOVE()", true},
    {"PART_SLIP", CALL, 0, 0, sc_part_slip, "PART_SLIP()", true},
    {"OBSTACLE", CALL | QUERY, 1, 1, sc_obstacle, "OBSTACLE(width) | OBSTACLE?", true},
    {"OBSTACLE_REMOVE", CALL, 0, 0, sc_obstacle_remove, "OBSTACLE_REMOVE()", true},
    {"AMBIENT", SET | QUERY, 0, 0, sc_ambient, "AMBIENT=celsius | AMBIENT?", true},
    {"PHYSICS", QUERY, 0, 0, sc_physics, "PHYSICS?", true},
    {"BODIES", QUERY, 0, 0, sc_bodies, "BODIES?", true},
    {"BODY", CALL, 1, 1, sc_body, "BODY(name)", true},
    {"CONTACTS", QUERY, 0, 0, sc_contacts, "CONTACTS?", true},
    {"PLACE", CALL, 4, 4, sc_place, "PLACE(body,x,y,z)", true},
    {"LIFT", CALL, 1, 2, sc_lift, "LIFT(dz[,speed])", true},
    {"PULL", CALL, 4, 4, sc_pull, "PULL(body,fx,fy,fz)", true},
    {"MASS", CALL, 2, 2, sc_mass, "MASS(body,kg)", true},
    {"FRICTION", CALL, 2, 2, sc_friction, "FRICTION(body,mu)", true},
    {"FAULT", CALL, 1, 2, sc_fault, "FAULT(name[,finger])", true},
    {"CLEAR", CALL, 0, 2, sc_clear, "CLEAR([name[,finger]])", true},
    {"FAULTS", QUERY, 0, 0, sc_faults, "FAULTS?", true},
    {"DELAY", CALL, 1, 2, sc_delay, "DELAY(ms[,session])", true},
    {"FAILNEXT", CALL, 2, 2, sc_failnext, "FAILNEXT(command,code)", true},
    {"CUT", CALL, 0, 1, sc_cut, "CUT([session])", true},
    {"NET", CALL | QUERY, 1, 2, sc_net, "NET(conditions[,session]) | NET?", true},
    {"STATE", QUERY, 0, 0, sc_state, "STATE?", true},
    {"SESSIONS", QUERY, 0, 0, sc_sessions, "SESSIONS?", true},
    {"RESET", CALL, 0, 0, sc_reset, "RESET()", true},
    {"COVERAGE", QUERY, 0, 0, sc_coverage, "COVERAGE?", true},
    {"COVERAGE_RESET", CALL, 0, 0, sc_coverage_reset, "COVERAGE_RESET()", true},
    {"DRIVER", QUERY, 0, 0, sc_driver, "DRIVER?", true},
    {"LOG", CALL, 1, 1, sc_log, "LOG(text)", true},
    {"HELP", QUERY, 0, 0, help, "HELP?", true},
    {"DEVICE", SET | QUERY, 0, 0, sc_device, "DEVICE=index | DEVICE?", false},
    {"DEVICES", QUERY, 0, 0, sc_devices, "DEVICES?", true},
    {"SCRIPT_RUN", CALL, 1, 1, sc_script_run, "SCRIPT_RUN(file)", true},
    {"SCRIPT_STOP", CALL, 0, 0, sc_script_stop, "SCRIPT_STOP()", true},
    {"SCRIPT", QUERY, 0, 0, sc_script, "SCRIPT?", true},
    {"BYE", CALL, 0, 0, sc_bye, "BYE()", false},
};

#define TABLE_COUNT (sizeof(table) / sizeof(table[0]))

/* HELP? lists the usage of every command; here, beside the table, so no
 * handler file refers back to it. */
static wsg_status_t help(simctl_ctx_t *ctx)
{
    cJSON *list = cJSON_CreateArray();
    for (size_t i = 0; i < TABLE_COUNT; i++) {
        cJSON_AddItemToArray(list, cJSON_CreateString(table[i].usage));
    }
    sc_reply_json(ctx, list);
    return E_SUCCESS;
}

static const simctl_entry_t *find(const char *name)
{
    for (size_t i = 0; i < TABLE_COUNT; i++) {
        if (strcmp(table[i].name, name) == 0) {
            return &table[i];
        }
    }
    return NULL;
}

/* ---- dispatch ---- */

static wsg_status_t check_shape(const simctl_entry_t *e, const gcl_command_t *cmd, char *why,
                                size_t cap)
{
    if ((e->forms & (unsigned)cmd->form) == 0u) {
        snprintf(why, cap, "wrong form; usage: %s", e->usage);
        return E_CMD_FORMAT_ERROR;
    }
    if (cmd->form == GCL_FORM_CALL && cmd->argc < e->min_args) {
        snprintf(why, cap, "not enough arguments; usage: %s", e->usage);
        return E_NOT_ENOUGH_PARAMS;
    }
    if (cmd->form == GCL_FORM_CALL && cmd->argc > e->max_args) {
        snprintf(why, cap, "too many arguments; usage: %s", e->usage);
        return E_NO_PARAM_EXPECTED;
    }
    return E_SUCCESS;
}

/* A command whose text is longer than GCL's strings (a host path for
 * SCRIPT_RUN): the parser refused the argument, the shape is checked here
 * and the handler reads the text from the line (sc_long_text). */
static wsg_status_t long_text_call(const simctl_entry_t *e, const char *line, size_t len,
                                   gcl_command_t *cmd, wsg_status_t status)
{
    if (status != E_INVALID_PARAMETER || e == NULL ||
        (e->handler != sc_script_run && e->handler != sc_timing) ||
        !sc_quoted_call(line, len, NULL, GCL_LINE_MAX + 1)) {
        return status;
    }
    cmd->form = GCL_FORM_CALL;
    cmd->argc = 1;
    cmd->args[0].kind = GCL_ARG_STRING;
    cmd->args[0].text[0] = '\0';
    return E_SUCCESS;
}

/* Parses and looks the command up; the entry, or NULL with why set. */
static const simctl_entry_t *resolve(const char *line, size_t len, gcl_command_t *cmd,
                                     wsg_status_t *status, char *why, size_t cap)
{
    *status = wsg_gcl_parse_line(line, len, cmd);
    const simctl_entry_t *e = cmd->name[0] != '\0' ? find(cmd->name) : NULL;
    *status = long_text_call(e, line, len, cmd, *status);
    if (cmd->name[0] != '\0' && e == NULL) {
        *status = E_CMD_UNKNOWN;
        snprintf(why, cap, "unknown control command (HELP? lists them)");
        return NULL;
    }
    if (*status != E_SUCCESS) {
        snprintf(why, cap, "%s",
                 *status == E_INVALID_PARAMETER
                     ? "an argument is not a valid number, string or name"
                     : "not a command line (NAME(args), NAME?, NAME=value)");
        return NULL;
    }
    *status = check_shape(e, cmd, why, cap);
    return *status == E_SUCCESS ? e : NULL;
}

/* Runs the handler in check-only mode when the command has arguments (what
 * a command without them can meet, e.g. no part to remove, depends on the
 * state when it runs). */
static bool check_arguments(simctl_t *ctl, const simctl_entry_t *e, const gcl_command_t *cmd,
                            const char *line, size_t len, char *why, size_t cap)
{
    if (cmd->form == GCL_FORM_QUERY || cmd->argc == 0) {
        return true;
    }
    simctl_ctx_t ctx = {.ctl = ctl,
                        .cmd = cmd,
                        .line = line,
                        .line_len = len,
                        .gripper = fleet_gripper(simctl_fleet(ctl), 0),
                        .check_only = true};
    wsg_status_t status = e->handler(&ctx);
    free(ctx.reply);
    if (status != E_SUCCESS) {
        snprintf(why, cap, "ERR %s %d %s", e->name, (int)status, ctx.why);
    }
    return status == E_SUCCESS;
}

bool simctl_check(simctl_t *ctl, const char *line, size_t len, bool for_scenario, char *why,
                  size_t cap)
{
    gcl_command_t cmd;
    wsg_status_t status = E_SUCCESS;
    const simctl_entry_t *e = resolve(line, len, &cmd, &status, why, cap);
    if (e != NULL && for_scenario && !e->in_scenario) {
        snprintf(why, cap, "%s cannot be used in a scenario", e->name);
        return false;
    }
    return e != NULL && check_arguments(ctl, e, &cmd, line, len, why, cap);
}

static char *error_line(const char *name, wsg_status_t status, const char *why)
{
    char *text = NULL;
    if (asprintf(&text, "ERR %s %d %s", name[0] != '\0' ? name : "?", (int)status, why) < 0) {
        return NULL;
    }
    return text;
}

static char *ack_line(const char *name)
{
    char *text = NULL;
    return asprintf(&text, "ACK %s", name) < 0 ? NULL : text;
}

char *simctl_exec(simctl_t *ctl, const char *line, size_t len, unsigned *selected,
                  simctl_outcome_t *outcome)
{
    gcl_command_t cmd;
    wsg_status_t status = E_SUCCESS;
    unsigned index =
        selected != NULL && *selected < fleet_count(simctl_fleet(ctl)) ? *selected : 0u;
    simctl_ctx_t ctx = {.ctl = ctl,
                        .cmd = &cmd,
                        .line = line,
                        .line_len = len,
                        .gripper = fleet_gripper(simctl_fleet(ctl), index),
                        .selected = selected};
    const simctl_entry_t *e = resolve(line, len, &cmd, &status, ctx.why, sizeof(ctx.why));
    wsg_sim_world_advance(&ctx.gripper->world,
                          hal_clock_now_us()); /* act on the world as it is now */
    if (e != NULL) {
        status = e->handler(&ctx);
        gripper_touch(ctx.gripper); /* its deadline may have moved */
    }
    if (outcome != NULL) {
        outcome->close = ctx.close;
        outcome->deferred = ctx.deferred;
    }
    if (ctx.deferred && outcome != NULL) {
        return NULL;
    }
    if (ctx.deferred) {
        simctl_step_finish(simctl_scheduler(ctl));
        ctx.reply = simctl_step_reply(ctl);
    }
    if (status != E_SUCCESS) {
        free(ctx.reply);
        ctx.reply = error_line(cmd.name, status, ctx.why);
    } else if (ctx.reply == NULL) {
        ctx.reply = ack_line(cmd.name);
    }
    return ctx.reply != NULL ? ctx.reply : strdup("ERR ? 10 out of memory");
}
