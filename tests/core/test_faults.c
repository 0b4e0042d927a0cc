/* SPDX-License-Identifier: BSD-3-Clause */
/* Severe faults (motor current, power, temperature) raise FAST STOP by
 * themselves and block its acknowledge while they persist. */
#include <check.h>

#include "fake_device.h"
#include "unit_suites.h"

START_TEST(current_fault_raises_fast_stop)
{
    h_world.axis.current_fault = true;
    advance_ms(1);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
    ck_assert_int_eq(ask_flag(SF_CURR_FAULT), 1);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7");
    ck_assert(h_log_contains(HAL_LOG_WARN, "severe fault"));
    EXPECT_NONE();
}
END_TEST

START_TEST(fsack_refused_while_fault_persists)
{
    h_world.axis.current_fault = true;
    advance_ms(1);
    ASK_EQ("FSACK()", "ERR FSACK 16");
    advance_ms(100);
    ASK_EQ("FSACK()", "ERR FSACK 16");
    ASK_EQ("MOVE(50)", "ERR MOVE 16");
    h_world.axis.current_fault = false;
    advance_ms(1);
    ck_assert_int_eq(ask_flag(SF_CURR_FAULT), 0);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1); /* latched until acknowledged */
    ASK_EQ("FSACK()", "ACK FSACK");
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 0);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    ASK_EQ("MOVE(50)", "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
}
END_TEST

START_TEST(fault_aborts_running_motion)
{
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(100);
    h_world.axis.current_fault = true;
    AWAIT("ERR MOVE 19", 1);
    EXPECT_NONE();
    advance_ms(100);
    ASK_EQ("SPEED?", "SPEED=0.0");
}
END_TEST

START_TEST(fault_seen_by_a_command_between_steps)
{
    h_world.axis.current_fault = true;
    ASK_EQ("MOVE(50)", "ERR MOVE 16"); /* the command reads the hardware first */
}
END_TEST

START_TEST(power_fault)
{
    h_world.axis.power_fault = true;
    advance_ms(1);
    ck_assert_int_eq(ask_flag(SF_POWER_FAULT), 1);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
    ASK_EQ("FSACK()", "ERR FSACK 16");
    h_world.axis.power_fault = false;
    ASK_EQ("FSACK()", "ACK FSACK");
    ck_assert_int_eq(ask_flag(SF_POWER_FAULT), 0);
}
END_TEST

START_TEST(temperature_fault)
{
    h_world.thermal.override_c = 75.0f;
    advance_ms(1);
    ASK_EQ("TEMP?", "TEMP=75.0");
    ck_assert_int_eq(ask_flag(SF_TEMP_FAULT), 1);
    ck_assert_int_eq(ask_flag(SF_TEMP_WARNING), 1);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
    ASK_EQ("FSACK()", "ERR FSACK 16");
    h_world.thermal.override_c = 50.0f;
    ASK_EQ("FSACK()", "ACK FSACK");
    ck_assert_int_eq(ask_flag(SF_TEMP_FAULT), 0);
    ck_assert_int_eq(ask_flag(SF_TEMP_WARNING), 0);
}
END_TEST

START_TEST(fault_raised_once)
{
    h_world.axis.current_fault = true;
    advance_ms(1);
    size_t logged = h_log_count();
    advance_ms(500);
    ck_assert_uint_eq(h_log_count(), logged); /* not re-raised every step */
}
END_TEST

START_TEST(faststop_command_while_faulted)
{
    h_world.axis.current_fault = true;
    advance_ms(1);
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    ASK_EQ("FSACK()", "ERR FSACK 16");
}
END_TEST

Suite *faults_suite(void)
{
    Suite *s = suite_create("faults");
    TCase *tc = tcase_create("severe");
    tcase_add_checked_fixture(tc, h_setup_homed, h_teardown);
    tcase_add_test(tc, current_fault_raises_fast_stop);
    tcase_add_test(tc, fsack_refused_while_fault_persists);
    tcase_add_test(tc, fault_aborts_running_motion);
    tcase_add_test(tc, fault_seen_by_a_command_between_steps);
    tcase_add_test(tc, power_fault);
    tcase_add_test(tc, temperature_fault);
    tcase_add_test(tc, fault_raised_once);
    tcase_add_test(tc, faststop_command_while_faulted);
    suite_add_tcase(s, tc);
    return s;
}
