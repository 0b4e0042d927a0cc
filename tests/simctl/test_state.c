/* SPDX-License-Identifier: BSD-3-Clause */
/* STATE, SESSIONS, RESET, COVERAGE, HELP and bad control lines. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <string.h>

#include "gripper.h"
#include "harness.h"

#include "fleet.h"
#include "simctl/commands.h"
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
    tcase_add_test(tc, bad_control_lines_get_clear_errors);
    tcase_add_test(tc, help_lists_every_command);
    tcase_add_test(tc, scenarios_cannot_step_or_say_bye);
    suite_add_tcase(s, tc);
    return s;
}
