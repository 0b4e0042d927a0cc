/* SPDX-License-Identifier: BSD-3-Clause */
/* FAULT, CLEAR, FAULTS, DELAY, FAILNEXT, CUT: injected faults and the core. */
#include <stdio.h>
#include <string.h>

#include "gripper.h"
#include "harness.h"

#include "fleet.h"
#include "wsg/wsg_types.h"

START_TEST(temperature_fault_refuses_motion_until_cleared_and_acknowledged)
{
    CTL_EQ("FAULT(\"TEMP_FAULT\")", "ACK FAULT");
    ck_assert_int_eq(t_flag(SF_TEMP_FAULT), 1);
    ck_assert_int_eq(t_flag(SF_FAST_STOP), 1);
    GCL_EQ("MOVE(50)", "ERR MOVE 16");
    GCL_EQ("FSACK()", "ERR FSACK 16"); /* the cause persists */
    CTL_EQ("CLEAR(\"TEMP_FAULT\")", "ACK CLEAR");
    ck_assert_int_eq(t_flag(SF_TEMP_FAULT), 0);
    GCL_EQ("MOVE(50)", "ERR MOVE 16"); /* still needs the acknowledge */
    GCL_EQ("FSACK()", "ACK FSACK");
    GCL_EQ("MOVE(50)", "ACK MOVE");
    ck_assert_int_ge(t_until("FIN MOVE", 3000), 0);
}
END_TEST

START_TEST(temperature_warning_only_warns)
{
    CTL_EQ("FAULT(TEMP_WARNING)", "ACK FAULT");
    ck_assert_int_eq(t_flag(SF_TEMP_WARNING), 1);
    ck_assert_int_eq(t_flag(SF_TEMP_FAULT), 0);
    ck_assert_int_eq(t_flag(SF_FAST_STOP), 0);
    GCL_EQ("TEMP?", "TEMP=65.0");
    GCL_EQ("MOVE(50)", "ACK MOVE");
    CTL_EQ("CLEAR(TEMP_WARNING)", "ACK CLEAR");
    ck_assert_int_eq(t_flag(SF_TEMP_WARNING), 0);
}
END_TEST

static void check_severe(const char *fault, int flag)
{
    char line[64];
    snprintf(line, sizeof(line), "FAULT(\"%s\")", fault);
    CTL_EQ(line, "ACK FAULT");
    ck_assert_int_eq(t_flag(flag), 1);
    ck_assert_int_eq(t_flag(SF_FAST_STOP), 1);
    ck_assert_int_eq(t_gripstate(), GS_ERROR);
    GCL_EQ("FSACK()", "ERR FSACK 16");
    snprintf(line, sizeof(line), "CLEAR(\"%s\")", fault);
    CTL_EQ(line, "ACK CLEAR");
    ck_assert_int_eq(t_flag(flag), 0);
    GCL_EQ("FSACK()", "ACK FSACK");
    ck_assert_int_eq(t_flag(SF_FAST_STOP), 0);
}

START_TEST(power_fault_needs_clearing_and_acknowledging)
{
    check_severe("POWER", SF_POWER_FAULT);
}
END_TEST

START_TEST(motor_current_fault_needs_clearing_and_acknowledging)
{
    check_severe("CURRENT", SF_CURR_FAULT);
}
END_TEST

START_TEST(unknown_fault_is_refused_and_changes_nothing)
{
    ck_assert_str_eq(ctl("FAULTS?"), "FAULTS=[]");
    CTL_ERR("FAULT(\"MELTDOWN\")", 24);
    CTL_ERR("FAULT(3)", 24);
    CTL_ERR("FAULT(\"FINGER\",2)", 28);
    CTL_ERR("FAULT()", 13);
    ck_assert_str_eq(ctl("FAULTS?"), "FAULTS=[]");
    ck_assert_int_eq(t_flag(SF_FAST_STOP), 0);
}
END_TEST

START_TEST(integer_arguments_are_whole_numbers_in_range)
{
    /* a fraction is not rounded to a finger, a huge value is not converted */
    CTL_ERR("FAULT(\"FINGER_POWER\",0.9)", 28);
    CTL_ERR("FAULT(\"FINGER_POWER\",-0.5)", 28);
    CTL_ERR("FAULT(\"FINGER_POWER\",1e300)", 28);
    CTL_ERR("FAULT(\"FINGER_POWER\",-1e300)", 28);
    CTL_ERR("FAULT(\"FINGER_POWER\",\"0\")", 24);
    CTL_ERR("CLEAR(\"POWER\",2147483648)", 28);
    CTL_ERR("CLEAR(\"POWER\",1)", 12); /* POWER has no finger */
    CTL_ERR("CLEAR(\"DELAY\",1)", 12);
    CTL_ERR("FAILNEXT(\"MOVE\",1e300)", 28);
    CTL_ERR("FAILNEXT(\"MOVE\",-1e300)", 28);
    CTL_ERR("DELAY(10,1e300)", 28);
    CTL_ERR("DELAY(10,0.5)", 28);
    CTL_ERR("CUT(-1)", 28);
    CTL_ERR("CUT(4294967297.5)", 28);
    ck_assert_str_eq(ctl("FAULTS?"), "FAULTS=[]");
    ck_assert_str_eq(ctl("FAULT(\"FINGER_POWER\",1e-300)"),
                     "ERR FAULT 28 the finger must be an integer 0 to 1");
    CTL_EQ("FAULT(\"FINGER_POWER\",1.0)", "ACK FAULT"); /* 1.0 is the integer 1 */
    ck_assert_ptr_nonnull(strstr(ctl("FAULTS?"), "FINGER1_POWER"));
    CTL_EQ("CLEAR(\"FINGER_POWER\",1)", "ACK CLEAR");
    CTL_EQ("FAULTS?", "FAULTS=[]");
}
END_TEST

START_TEST(faults_are_listed_until_cleared)
{
    CTL_EQ("FAULT(POWER)", "ACK FAULT");
    CTL_EQ("FAILNEXT(\"GRIP\",18)", "ACK FAILNEXT");
    const char *list = ctl("FAULTS?");
    ck_assert_ptr_nonnull(strstr(list, "\"fault\":\"POWER\""));
    ck_assert_ptr_nonnull(strstr(list, "\"fault\":\"FAILNEXT\",\"command\":\"GRIP\",\"code\":18"));
    CTL_EQ("CLEAR()", "ACK CLEAR");
    CTL_EQ("FAULTS?", "FAULTS=[]");
}
END_TEST

START_TEST(failnext_fails_the_next_command_once)
{
    CTL_EQ("FAILNEXT(move,18)", "ACK FAILNEXT");
    GCL_EQ("POS?", "POS=110.0"); /* other commands are not affected */
    GCL_EQ("MOVE(50)", "ERR MOVE 18");
    ck_assert_int_eq(t_flag(SF_CMD_FAILURE), 1);
    GCL_EQ("MOVE(50)", "ACK MOVE");
    CTL_EQ("FAULTS?", "FAULTS=[]");
}
END_TEST

START_TEST(failnext_rejects_bad_input)
{
    CTL_ERR("FAILNEXT(\"FLY\",18)", 24);
    CTL_ERR("FAILNEXT(\"MOVE\",0)", 28);
    CTL_ERR("FAILNEXT(\"MOVE\",31)", 28);
    CTL_ERR("FAILNEXT(\"MOVE\",2.5)", 28);
    CTL_ERR("FAILNEXT(18,\"MOVE\")", 24);
    CTL_EQ("FAULTS?", "FAULTS=[]");
    GCL_EQ("MOVE(50)", "ACK MOVE");
}
END_TEST

static char session_arg[32];

static const char *with_session(const char *fmt)
{
    snprintf(session_arg, sizeof(session_arg), fmt, (unsigned)wsg_conn_id(&t_gcl.conn));
    return session_arg;
}

START_TEST(delay_holds_the_next_reply_on_the_simulated_clock)
{
    CTL_EQ(with_session("DELAY(50,%u)"), "ACK DELAY");
    ck_assert_str_eq(gcl("POS?"), "<no reply>");
    ck_assert_str_eq(gcl("SPEED?"), "<no reply>"); /* later replies queue behind it */
    t_step_ms(49);
    ck_assert_uint_eq(gcl_unread(), 0);
    t_step_ms(1);
    ck_assert_str_eq(gcl_next(), "POS=110.0");
    ck_assert_str_eq(gcl_next(), "SPEED=0.0");
    GCL_EQ("POS?", "POS=110.0"); /* only the next reply was delayed */
    CTL_EQ("FAULTS?", "FAULTS=[]");
}
END_TEST

START_TEST(delay_shows_and_clears)
{
    CTL_EQ("DELAY(100)", "ACK DELAY");
    ck_assert_ptr_nonnull(strstr(ctl("FAULTS?"), "\"fault\":\"DELAY\""));
    ck_assert_str_eq(gcl("POS?"), "<no reply>");
    CTL_EQ("CLEAR(\"DELAY\")", "ACK CLEAR"); /* held lines are delivered */
    ck_assert_str_eq(gcl_next(), "POS=110.0");
    CTL_EQ("FAULTS?", "FAULTS=[]");
    CTL_ERR("DELAY(0)", 28);
    CTL_ERR("DELAY(10,999)", 21);
}
END_TEST

/* A GCL session that counts its lines and checks they alternate SN / TAG. */
typedef struct {
    unsigned lines;
    unsigned out_of_order;
} counting_client_t;

static void count_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    counting_client_t *c = ctx;
    (void)kind;
    const char *expect = c->lines % 2 == 0 ? "SN=" : "TAG=";
    c->out_of_order += len < 4 || strncmp(line, expect, strlen(expect)) != 0 ? 1u : 0u;
    c->lines++;
}

#define FLOOD_LINES 40000u /* about 560 KB of replies, past the 256 KiB hold */

static bool flood_delayed_session(void *arg)
{
    wsg_conn_t *s = arg;
    for (unsigned i = 0; i < FLOOD_LINES; i++) {
        const char *line = i % 2 == 0 ? "SN?\n" : "TAG?\n";
        gripper_feed(fleet_gripper(t_fleet, 0), s, (const uint8_t *)line, strlen(line), 0);
    }
    return true;
}

static unsigned count_of(const char *text, const char *what)
{
    unsigned n = 0;
    for (const char *p = strstr(text, what); p != NULL; p = strstr(p + 1, what)) {
        n++;
    }
    return n;
}

START_TEST(delay_never_drops_a_reply)
{
    static const wsg_conn_io_t counting_io = {.write = count_line};
    static wsg_conn_t conn;
    wsg_conn_t *s = &conn;
    counting_client_t client = {0, 0};
    wsg_conn_open(s, &fleet_gripper(t_fleet, 0)->device, &wsg_gcl_driver, WSG_TRANSPORT_STREAM,
                  &counting_io, &client);
    char line[48];
    snprintf(line, sizeof(line), "DELAY(60000,%u)", (unsigned)wsg_conn_id(s));
    CTL_EQ(line, "ACK DELAY");
    bool ok = false;
    const char *log = t_capture_stderr(flood_delayed_session, s, &ok);
    /* the hold overflowed: the delay ended early and every reply went out */
    ck_assert_uint_eq(client.lines, FLOOD_LINES);
    ck_assert_uint_eq(client.out_of_order, 0);
    ck_assert_uint_eq(count_of(log, "ended early"), 1);
    ck_assert_ptr_nonnull(strstr(log, "warning: DELAY of session"));
    CTL_EQ("FAULTS?", "FAULTS=[]");
    t_step_ms(60000);
    ck_assert_uint_eq(client.lines, FLOOD_LINES);
    wsg_conn_close(s, WSG_CLOSE_ANNOUNCED);
}
END_TEST

START_TEST(cut_needs_a_connection)
{
    /* this session has no socket behind it: the e2e tests cut real ones */
    CTL_ERR(with_session("CUT(%u)"), 21);
    CTL_ERR("CUT(999)", 21);
    CTL_ERR("CUT()", 21);
    GCL_EQ("POS?", "POS=110.0");
}
END_TEST

START_TEST(finger_fault_reaches_the_finger)
{
    CTL_EQ("FAULT(\"FINGER_POWER\",0)", "ACK FAULT");
    ck_assert_ptr_nonnull(strstr(ctl("FAULTS?"), "FINGER0_POWER"));
    t_step_ms(500);
    ck_assert_int_eq(t_flag(SF_FINGER_FAULT), 1);
    CTL_EQ("CLEAR(\"FINGER_POWER\",0)", "ACK CLEAR");
    t_step_ms(500);
    ck_assert_int_eq(t_flag(SF_FINGER_FAULT), 0);
}
END_TEST

/* Every device of a fleet has its own hardware faults. */

static bool has_flag(unsigned device, int flag)
{
    return (t_device_flags(device) & (1u << flag)) != 0u;
}

START_TEST(a_fault_acts_on_the_selected_device_only)
{
    ck_assert_str_eq(ctl_on(2, "FAULT(\"TEMP_WARNING\")"), "ACK FAULT");
    ck_assert(has_flag(2, SF_TEMP_WARNING));
    ck_assert(!has_flag(0, SF_TEMP_WARNING));
    ck_assert(!has_flag(1, SF_TEMP_WARNING));
    GCL_EQ("TEMP?", "TEMP=34.0"); /* device 0's board keeps its temperature */
    ck_assert_str_eq(ctl_on(0, "FAULTS?"), "FAULTS=[]");
    ck_assert_str_eq(ctl_on(1, "FAULTS?"), "FAULTS=[]");
    ck_assert_ptr_nonnull(strstr(ctl_on(2, "FAULTS?"), "\"fault\":\"TEMP_WARNING\""));
    ck_assert_str_eq(ctl_on(0, "FAULT(POWER)"), "ACK FAULT");
    ck_assert(has_flag(0, SF_POWER_FAULT));
    ck_assert(has_flag(0, SF_FAST_STOP));
    ck_assert(!has_flag(2, SF_POWER_FAULT));
    ck_assert(!has_flag(2, SF_FAST_STOP));
    ck_assert(has_flag(2, SF_TEMP_WARNING)); /* device 0's fault left device 2's alone */
}
END_TEST

START_TEST(clearing_acts_on_the_selected_device_only)
{
    ck_assert_str_eq(ctl_on(0, "FAULT(TEMP_WARNING)"), "ACK FAULT");
    ck_assert_str_eq(ctl_on(2, "FAULT(TEMP_WARNING)"), "ACK FAULT");
    ck_assert_str_eq(ctl_on(2, "FAULT(CURRENT)"), "ACK FAULT");
    ck_assert_str_eq(ctl_on(2, "CLEAR(TEMP_WARNING)"), "ACK CLEAR");
    ck_assert(!has_flag(2, SF_TEMP_WARNING));
    ck_assert(has_flag(2, SF_CURR_FAULT));
    ck_assert(has_flag(0, SF_TEMP_WARNING));
    ck_assert_str_eq(ctl_on(2, "CLEAR()"), "ACK CLEAR");
    ck_assert(!has_flag(2, SF_CURR_FAULT));
    ck_assert_str_eq(ctl_on(2, "FAULTS?"), "FAULTS=[]");
    ck_assert(has_flag(0, SF_TEMP_WARNING)); /* device 2's CLEAR() left device 0's */
    GCL_EQ("TEMP?", "TEMP=65.0");
    ck_assert_str_eq(ctl_on(0, "CLEAR()"), "ACK CLEAR");
    ck_assert(!has_flag(0, SF_TEMP_WARNING));
}
END_TEST

START_TEST(a_reset_clears_the_faults_of_its_device_only)
{
    ck_assert_str_eq(ctl_on(0, "FAULT(TEMP_WARNING)"), "ACK FAULT");
    ck_assert_str_eq(ctl_on(1, "FAULT(TEMP_WARNING)"), "ACK FAULT");
    ck_assert_str_eq(ctl_on(1, "RESET()"), "ACK RESET");
    ck_assert_str_eq(ctl_on(1, "FAULTS?"), "FAULTS=[]");
    ck_assert(!has_flag(1, SF_TEMP_WARNING));
    ck_assert(has_flag(0, SF_TEMP_WARNING));
}
END_TEST

/* Every device has a finger bus of its own: a finger fault goes
 * to the selected device's finger and to no other device's. */
START_TEST(a_finger_fault_goes_to_the_devices_own_finger)
{
    ck_assert_str_eq(ctl_on(2, "FAULT(\"FINGER_POWER\",0)"), "ACK FAULT");
    ck_assert_ptr_nonnull(strstr(ctl_on(2, "FAULTS?"), "\"FINGER0_POWER\""));
    ck_assert_str_eq(ctl_on(0, "FAULTS?"), "FAULTS=[]");
    ck_assert_str_eq(ctl_on(2, "CLEAR(\"FINGER_POWER\",0)"), "ACK CLEAR");
    ck_assert_str_eq(ctl_on(2, "FAULTS?"), "FAULTS=[]");
}
END_TEST

Suite *faults_suite(void)
{
    Suite *s = suite_create("faults");
    TCase *tc = tcase_create("faults");
    tcase_add_checked_fixture(tc, t_setup_homed, t_teardown);
    tcase_add_test(tc, temperature_fault_refuses_motion_until_cleared_and_acknowledged);
    tcase_add_test(tc, temperature_warning_only_warns);
    tcase_add_test(tc, power_fault_needs_clearing_and_acknowledging);
    tcase_add_test(tc, motor_current_fault_needs_clearing_and_acknowledging);
    tcase_add_test(tc, unknown_fault_is_refused_and_changes_nothing);
    tcase_add_test(tc, integer_arguments_are_whole_numbers_in_range);
    tcase_add_test(tc, faults_are_listed_until_cleared);
    tcase_add_test(tc, failnext_fails_the_next_command_once);
    tcase_add_test(tc, failnext_rejects_bad_input);
    tcase_add_test(tc, delay_holds_the_next_reply_on_the_simulated_clock);
    tcase_add_test(tc, delay_shows_and_clears);
    tcase_add_test(tc, delay_never_drops_a_reply);
    tcase_add_test(tc, cut_needs_a_connection);
    tcase_add_test(tc, finger_fault_reaches_the_finger);
    suite_add_tcase(s, tc);
    TCase *fleet = tcase_create("faults of a fleet");
    tcase_add_checked_fixture(fleet, t_setup_three_devices, t_teardown);
    tcase_add_test(fleet, a_fault_acts_on_the_selected_device_only);
    tcase_add_test(fleet, clearing_acts_on_the_selected_device_only);
    tcase_add_test(fleet, a_reset_clears_the_faults_of_its_device_only);
    tcase_add_test(fleet, a_finger_fault_goes_to_the_devices_own_finger);
    suite_add_tcase(s, fleet);
    return s;
}
