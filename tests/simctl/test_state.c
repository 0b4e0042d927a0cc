/* SPDX-License-Identifier: BSD-3-Clause */
/* STATE, SESSIONS, RESET, COVERAGE, HELP and bad control lines. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <string.h>

#include "gripper.h"
#include "harness.h"

#include "fleet.h"
#include "simctl/commands.h"
#include "wsg/wsg_names.h"
#include "wsg/wsg_types.h"

/* The JSON after "NAME=" of a reply; the caller deletes it. */
static cJSON *reply_json(const char *line)
{
    const char *reply = ctl(line);
    const char *eq = strchr(reply, '=');
    ck_assert_msg(eq != NULL, "%s -> %s", line, reply);
    cJSON *json = cJSON_Parse(eq + 1);
    ck_assert_msg(json != NULL, "not JSON: %s", reply);
    return json;
}

static double number_at(const cJSON *root, const char *a, const char *b)
{
    const cJSON *item =
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(root, a), b);
    ck_assert_msg(cJSON_IsNumber(item), "%s.%s is not a number", a, b);
    return item->valuedouble;
}

START_TEST(state_dump_shows_the_device)
{
    CTL_EQ("PART(40,80,10)", "ACK PART");
    GCL_EQ("GRIP(40)", "ACK GRIP");
    ck_assert_int_ge(t_until("FIN GRIP", 3000), 0);
    GCL_EQ("AUTOSEND(\"FORCE\",50,1.5)", "ACK AUTOSEND");
    CTL_EQ("FAULT(TEMP_WARNING)", "ACK FAULT");
    cJSON *s = reply_json("STATE?");
    ck_assert_double_eq_tol(number_at(s, "axis", "position_mm"), 40.0, 1.0);
    ck_assert_double_eq(number_at(s, "grip", "state"), GS_HOLDING);
    ck_assert_str_eq(cJSON_GetObjectItem(cJSON_GetObjectItem(s, "grip"), "state_name")->valuestring,
                     "HOLDING");
    ck_assert_double_eq(number_at(cJSON_GetObjectItem(s, "grip"), "stats", "grips"), 1);
    ck_assert_double_eq(number_at(cJSON_GetObjectItem(s, "world"), "part", "slip_force_n"), 10);
    ck_assert_double_eq(number_at(s, "world", "board_temp_c"), 65);
    ck_assert(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetObjectItem(s, "time"), "paused")));
    char *flags = cJSON_PrintUnformatted(cJSON_GetObjectItem(s, "flags"));
    ck_assert_ptr_nonnull(strstr(flags, "\"SF_REFERENCED\""));
    ck_assert_ptr_nonnull(strstr(flags, "\"SF_TEMP_WARNING\""));
    cJSON_free(flags);
    char *faults = cJSON_PrintUnformatted(cJSON_GetObjectItem(s, "faults"));
    ck_assert_ptr_nonnull(strstr(faults, "\"TEMP_WARNING\""));
    cJSON_free(faults);
    const cJSON *session = cJSON_GetArrayItem(cJSON_GetObjectItem(s, "sessions"), 0);
    ck_assert_double_eq(cJSON_GetObjectItem(session, "id")->valuedouble, wsg_conn_id(&t_gcl.conn));
    char *subs = cJSON_PrintUnformatted(cJSON_GetObjectItem(session, "autosend"));
    ck_assert_str_eq(subs, "[{\"value\":\"FORCE\",\"interval_ms\":50,\"delta\":1.5,"
                           "\"on_change\":false,\"missed\":0}]");
    cJSON_free(subs);
    cJSON_Delete(s);
}
END_TEST

START_TEST(sessions_lists_the_open_sessions)
{
    char expect[64];
    snprintf(expect, sizeof(expect), "SESSIONS=[{\"id\":%u,\"transport\":\"tcp\"}]",
             (unsigned)wsg_conn_id(&t_gcl.conn));
    CTL_EQ("SESSIONS?", expect);
}
END_TEST

START_TEST(reset_returns_to_power_on)
{
    CTL_EQ("PART(40)", "ACK PART");
    CTL_EQ("FAULT(POWER)", "ACK FAULT");
    CTL_EQ("FAILNEXT(MOVE,4)", "ACK FAILNEXT");
    CTL_EQ("AMBIENT=40", "AMBIENT=40");
    CTL_EQ("RESET()", "ACK RESET");
    const wsg_snapshot_t *snap = wsg_device_snapshot(&fleet_gripper(t_fleet, 0)->device);
    ck_assert(!wsg_conn_is_open(&t_gcl.conn)); /* a power cycle ends every session */
    ck_assert(!snap->referenced);
    ck_assert_int_eq(snap->grip_state, GS_IDLE);
    ck_assert_uint_eq(snap->flags & WSG_FLAG(SF_FAST_STOP), 0);
    CTL_EQ("FAULTS?", "FAULTS=[]");
    CTL_EQ("PART?", "PART=[0,0,0,0]");
    CTL_EQ("AMBIENT?", "AMBIENT=25");
    CTL_EQ("SESSIONS?", "SESSIONS=[]");
}
END_TEST

START_TEST(coverage_reports_what_was_exercised)
{
    GCL_EQ("POS?", "POS=110.0");
    GCL_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=0");
    GCL_EQ("MOVE(500)", "ERR MOVE 28");
    GCL_EQ("VERBOSE=true", "VERBOSE=1");
    GCL_EQ("WARP()", "ERR WARP 14 Unknown command"); /* VERBOSE is on */
    cJSON *c = reply_json("COVERAGE?");
    char *text = cJSON_PrintUnformatted(c);
    ck_assert_ptr_nonnull(strstr(text, "{\"form\":\"POS?\",\"count\":1}"));
    ck_assert_ptr_nonnull(strstr(text, "{\"form\":\"GRIPSTATS[_]?\",\"count\":1}"));
    ck_assert_ptr_nonnull(strstr(text, "{\"form\":\"HOME()\",\"count\":1}"));
    ck_assert_ptr_nonnull(strstr(text, "\"code\":28,\"name\":\"E_RANGE_ERROR\",\"count\":1,"
                                       "\"commands\":[\"MOVE\"]"));
    ck_assert_ptr_nonnull(strstr(text, "{\"name\":\"WARP\",\"count\":1}"));
    ck_assert_ptr_nonnull(strstr(text, "\"IDLE -> POSITIONING\""));
    ck_assert_ptr_nonnull(strstr(text, "\"never_used\":[\"VERBOSE?\""));
    ck_assert_ptr_nonnull(strstr(text, "\"SF_REFERENCED\""));
    ck_assert_ptr_null(strstr(text, "\"tolerated\"")); /* only with --strict */
    cJSON_free(text);
    cJSON_Delete(c);
    CTL_EQ("COVERAGE_RESET()", "ACK COVERAGE_RESET");
    ck_assert_ptr_null(strstr(ctl("COVERAGE?"), "\"form\":\"POS?\""));
}
END_TEST

/* COVERAGE?'s "flags"."raised", as JSON text (static). */
static const char *raised_flags(void)
{
    static char text[1024];
    cJSON *c = reply_json("COVERAGE?");
    const cJSON *flags = cJSON_GetObjectItemCaseSensitive(c, "flags");
    char *raised = cJSON_PrintUnformatted(cJSON_GetObjectItemCaseSensitive(flags, "raised"));
    ck_assert_ptr_nonnull(raised);
    snprintf(text, sizeof(text), "%s", raised);
    cJSON_free(raised);
    cJSON_Delete(c);
    return text;
}

/* The names of the flags in a register, as "raised" lists them (static). */
static const char *flag_names(uint32_t flags)
{
    static char text[1024];
    size_t used = (size_t)snprintf(text, sizeof(text), "[");
    for (unsigned bit = 0; bit < WSG_SYSFLAG_COUNT; bit++) {
        const char *name = wsg_sysflag_name(bit);
        if (name != NULL && (flags & WSG_FLAG(bit)) != 0u) {
            used += (size_t)snprintf(text + used, sizeof(text) - used, "%s\"%s\"",
                                     text[used - 1] == '[' ? "" : ",", name);
        }
    }
    snprintf(text + used, sizeof(text) - used, "]");
    return text;
}

/* The coverage is shown a device's flags only by the control steps that
 * change them; after COVERAGE_RESET the next step shows them all the same,
 * as every step did before, though none changes. */
START_TEST(coverage_after_a_reset_has_the_flags_of_the_next_step)
{
    t_step_ms(10);
    uint32_t flags = t_device_flags(0);
    ck_assert_uint_ne(flags, 0u); /* homed: SF_REFERENCED at least */
    CTL_EQ("COVERAGE_RESET()", "ACK COVERAGE_RESET");
    ck_assert_str_eq(raised_flags(), "[]"); /* no step yet */
    t_step_ms(10);
    ck_assert_uint_eq(t_device_flags(0), flags); /* no step changed them */
    ck_assert_str_eq(raised_flags(), flag_names(flags));
}
END_TEST

/* Each flag register a step left, millisecond by millisecond through a
 * grip cycle with a failing command: the coverage raised exactly those
 * flags, though it was shown only the steps that changed them. */
START_TEST(coverage_raises_every_flag_a_step_left)
{
    static const char *const cycle[][2] = {{"MOVE(80)", "FIN MOVE"},
                                           {"GRIP(20)", "FIN GRIP"},
                                           {"MOVE(70)", "ERR MOVE"},
                                           {"RELEASE(10)", "FIN RELEASE"},
                                           {"MOVE(500)", NULL}};
    CTL_EQ("PART(30)", "ACK PART");
    CTL_EQ("COVERAGE_RESET()", "ACK COVERAGE_RESET");
    uint32_t seen = 0u;
    for (size_t i = 0; i < sizeof(cycle) / sizeof(cycle[0]); i++) {
        (void)gcl(cycle[i][0]);
        for (int ms = 0; ms < 5000 && cycle[i][1] != NULL; ms++) {
            t_step_ms(1);
            seen |= t_device_flags(0);
            if (gcl_unread() > 0 && strncmp(gcl_next(), cycle[i][1], strlen(cycle[i][1])) == 0) {
                break;
            }
        }
    }
    t_step_ms(1);
    seen |= t_device_flags(0);
    ck_assert(seen & WSG_FLAG(SF_MOVING));
    ck_assert(seen & WSG_FLAG(SF_CMD_FAILURE));
    ck_assert_str_eq(raised_flags(), flag_names(seen));
}
END_TEST

START_TEST(bad_control_lines_get_clear_errors)
{
    ck_assert_str_eq(ctl("WARP(9)"), "ERR WARP 14 unknown control command (HELP? lists them)");
    ck_assert_str_eq(ctl("PAUSE"),
                     "ERR PAUSE 15 not a command line (NAME(args), NAME?, NAME=value)");
    ck_assert_str_eq(ctl("PAUSE?"), "ERR PAUSE 15 wrong form; usage: PAUSE()");
    ck_assert_str_eq(ctl("STEP(1,)"),
                     "ERR STEP 15 not a command line (NAME(args), NAME?, NAME=value)");
    ck_assert_str_eq(ctl("PART(4x)"),
                     "ERR PART 24 an argument is not a valid number, string or name");
    ck_assert_str_eq(ctl("(1)"), "ERR ? 15 not a command line (NAME(args), NAME?, NAME=value)");
    ck_assert_uint_eq(gcl_unread(), 0);
}
END_TEST

START_TEST(help_lists_every_command)
{
    const char *help = ctl("HELP?");
    ck_assert_ptr_nonnull(strstr(help, "\"STEP(ms)\""));
    ck_assert_ptr_nonnull(strstr(help, "\"FAILNEXT(command,code)\""));
    CTL_EQ("LOG(\"checkpoint\")", "ACK LOG");
    CTL_EQ("BYE()", "ACK BYE");
}
END_TEST

START_TEST(scenarios_cannot_step_or_say_bye)
{
    char why[128];
    ck_assert(simctl_check(t_sim, "PART_SLIP()", 11, true, why, sizeof(why)));
    ck_assert(!simctl_check(t_sim, "STEP(5)", 7, true, why, sizeof(why)));
    ck_assert_str_eq(why, "STEP cannot be used in a scenario");
    ck_assert(simctl_check(t_sim, "STEP(5)", 7, false, why, sizeof(why)));
    ck_assert(!simctl_check(t_sim, "BYE()", 5, true, why, sizeof(why)));
    ck_assert(!simctl_check(t_sim, "PART(1,2,3,4)", 13, true, why, sizeof(why)));
}
END_TEST

Suite *state_suite(void)
{
    Suite *s = suite_create("state");
    TCase *tc = tcase_create("state");
    tcase_add_checked_fixture(tc, t_setup_homed, t_teardown);
    tcase_add_test(tc, state_dump_shows_the_device);
    tcase_add_test(tc, sessions_lists_the_open_sessions);
    tcase_add_test(tc, reset_returns_to_power_on);
    tcase_add_test(tc, coverage_reports_what_was_exercised);
    tcase_add_test(tc, coverage_after_a_reset_has_the_flags_of_the_next_step);
    tcase_add_test(tc, coverage_raises_every_flag_a_step_left);
    tcase_add_test(tc, bad_control_lines_get_clear_errors);
    tcase_add_test(tc, help_lists_every_command);
    tcase_add_test(tc, scenarios_cannot_step_or_say_bye);
    suite_add_tcase(s, tc);
    return s;
}
