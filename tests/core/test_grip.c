/* SPDX-License-Identifier: BSD-3-Clause */
/* GRIP and RELEASE, part detection, grip monitoring and GRIPSTATS. */
#include <check.h>
#include <math.h>

#include "fake_device.h"
#include "unit_suites.h"

#define STIFF_PART_N_MM 50.0f

static void place_part(float width_mm, float stiffness_n_mm)
{
    wsg_sim_axis_place_part(&h_world.axis, width_mm, stiffness_n_mm);
}

static void finish(const char *ack, const char *fin)
{
    ck_assert_str_eq(await_line(&h_main, 0), ack);
    ck_assert_str_eq(await_line(&h_main, 5000), fin);
    EXPECT_NONE();
}

static void grip(const char *line, const char *fin)
{
    SEND(line);
    finish("ACK GRIP", fin);
}

static void release(const char *line)
{
    SEND(line);
    finish("ACK RELEASE", "FIN RELEASE");
}

static void move_to(const char *line)
{
    SEND(line);
    finish("ACK MOVE", "FIN MOVE");
}

static void assert_pos(float expected, float tolerance)
{
    float pos = ask_float("POS?");
    ck_assert_msg(fabsf(pos - expected) <= tolerance, "POS %.3f, expected %.3f +- %.3f", pos,
                  expected, tolerance);
}

/* --- GRIP without a part width --- */

START_TEST(grip_without_part_grips_itself)
{
    SEND("GRIP()");
    EXPECT("ACK GRIP");
    advance_ms(100);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=1");
    ck_assert_str_eq(await_line(&h_main, 3000), "FIN GRIP");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    assert_pos(0.0f, 0.05f);
    ASK_EQ("FORCE?", "FORCE=40.0"); /* default force: half the nominal maximum */
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[1,0,0]");
}
END_TEST

START_TEST(grip_part_holds_at_its_width)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP()", "FIN GRIP");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    /* the part yields by force / stiffness */
    assert_pos(30.0f - 40.0f / STIFF_PART_N_MM, 0.05f);
    ASK_EQ("FORCE?", "FORCE=40.0");
    advance_ms(500);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4"); /* monitoring sees a firm grip */
}
END_TEST

START_TEST(grip_with_force)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP(20)", "FIN GRIP");
    ASK_EQ("FORCE?", "FORCE=20.0");
    assert_pos(30.0f - 20.0f / STIFF_PART_N_MM, 0.05f);
}
END_TEST

START_TEST(grip_rigid_part)
{
    place_part(42.5f, 0.0f);
    grip("GRIP(10.5)", "FIN GRIP");
    ASK_EQ("POS?", "POS=42.5");
    ASK_EQ("FORCE?", "FORCE=10.5");
}
END_TEST

START_TEST(grip_without_width_ignores_clt)
{
    /* cases 1 and 2 always grip something, even with a clamping travel of 0 */
    ASK_EQ("CLT=0", "CLT=0.0");
    grip("GRIP()", "FIN GRIP");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    ASK_EQ("POS?", "POS=0.0");
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[1,0,0]");
}
END_TEST

/* --- GRIP with a part width: part detection --- */

START_TEST(grip_width_part_inside_tolerance)
{
    place_part(33.0f, 0.0f);
    grip("GRIP(40, 30)", "FIN GRIP");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    ASK_EQ("POS?", "POS=33.0");
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[1,0,0]");
}
END_TEST

START_TEST(grip_width_part_exactly_at_width)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP(40,30)", "FIN GRIP");
    assert_pos(30.0f - 40.0f / STIFF_PART_N_MM, 0.05f);
}
END_TEST

START_TEST(grip_width_part_far_outside_tolerance)
{
    place_part(45.0f, 0.0f);
    grip("GRIP(40, 30)", "ERR GRIP 29");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7");
    ck_assert_int_eq(ask_flag(SF_BLOCKED_MINUS), 1);
    ASK_EQ("POS?", "POS=45.0");
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[1,0,0]");
    release("RELEASE()"); /* opening after a collision is allowed (2.2.4) */
    ASK_EQ("POS?", "POS=55.0");
}
END_TEST

START_TEST(grip_width_without_part)
{
    grip("GRIP(40, 30)", "ERR GRIP 18");
    ck_assert_int_eq(ask_flag(SF_CMD_FAILURE), 1);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=2");
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[1,1,0]");
    advance_ms(200);
    /* the jaws stop after the clamping travel beyond the nominal width */
    assert_pos(30.0f - 10.0f, 1.0f);
    release("RELEASE()"); /* allowed from NO PART */
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
}
END_TEST

START_TEST(grip_pwt_widens_the_band)
{
    ASK_EQ("PWT=20", "PWT=20.0");
    place_part(45.0f, 0.0f);
    grip("GRIP(40, 30)", "FIN GRIP");
    ASK_EQ("POS?", "POS=45.0");
}
END_TEST

START_TEST(grip_pwt_of_another_session_does_not_apply)
{
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "PWT=20"), "PWT=20.0");
    place_part(45.0f, 0.0f);
    grip("GRIP(40, 30)", "ERR GRIP 29");
}
END_TEST

START_TEST(grip_clt_limits_the_travel)
{
    ASK_EQ("CLT=2", "CLT=2.0");
    grip("GRIP(40, 30)", "ERR GRIP 18");
    advance_ms(200);
    assert_pos(28.0f, 1.0f);
}
END_TEST

START_TEST(grip_soft_part_beyond_clamping_travel)
{
    /* contact at 30 but the force needs 8 mm of travel: more than CLT 2 */
    ASK_EQ("CLT=2", "CLT=2.0");
    place_part(30.0f, 5.0f);
    grip("GRIP(40, 30)", "ERR GRIP 18");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=2");
}
END_TEST

START_TEST(grip_with_speed_limit)
{
    place_part(30.0f, 0.0f);
    SEND("GRIP(40, 30, 20)");
    EXPECT("ACK GRIP");
    advance_ms(1000);
    ASK_EQ("SPEED?", "SPEED=20.0");
    ck_assert_str_eq(await_line(&h_main, 5000), "FIN GRIP");
    ASK_EQ("POS?", "POS=30.0");
}
END_TEST

START_TEST(grip_outside)
{
    move_to("MOVE(20)");
    place_part(40.0f, 0.0f); /* a ring around the jaws */
    grip("GRIP(40, 40)", "FIN GRIP");
    ASK_EQ("POS?", "POS=40.0");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    release("RELEASE(5)"); /* pulls back inwards */
    ASK_EQ("POS?", "POS=35.0");
}
END_TEST

START_TEST(grip_outside_collision)
{
    move_to("MOVE(20)");
    place_part(25.0f, 0.0f); /* met 15 mm before the nominal 40 mm */
    grip("GRIP(40, 40)", "ERR GRIP 29");
    ck_assert_int_eq(ask_flag(SF_BLOCKED_PLUS), 1);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7");
}
END_TEST

START_TEST(grip_outside_without_part)
{
    move_to("MOVE(20)");
    grip("GRIP(40, 40)", "ERR GRIP 18");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=2");
    advance_ms(200);
    assert_pos(40.0f + 10.0f, 1.0f);
}
END_TEST

/* --- GRIP state rules --- */

START_TEST(grip_while_holding_is_denied)
{
    grip("GRIP()", "FIN GRIP");
    ASK_EQ("GRIP()", "ERR GRIP 16");
    ASK_EQ("GRIP(40, 30)", "ERR GRIP 16");
    ASK_EQ("GRIPSTATS[0]?", "GRIPSTATS[0]=1");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
}
END_TEST

START_TEST(stop_during_grip)
{
    SEND("GRIP()");
    EXPECT("ACK GRIP");
    advance_ms(200);
    SEND("STOP()");
    EXPECT("ERR GRIP 19");
    EXPECT("ACK STOP");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    /* manual 2.2.4: the last motion command was a GRIP, whatever its outcome */
    release("RELEASE()");
}
END_TEST

/* manual 3.2.1: STOP ends a movement, not a grip */
START_TEST(stop_while_holding_keeps_the_grip)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP(20,30)", "FIN GRIP");
    ASK_EQ("STOP()", "ACK STOP");
    advance_ms(100);
    EXPECT_NONE();
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    ASK_EQ("FORCE?", "FORCE=20.0"); /* still clamped */
    ck_assert_int_eq(ask_flag(SF_AXIS_STOPPED), 1);
    ASK_EQ("GRIP(20,30)", "ERR GRIP 16");
    release("RELEASE(10)");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
}
END_TEST

START_TEST(stop_keeps_no_part)
{
    grip("GRIP(40, 40)", "ERR GRIP 18");
    ASK_EQ("STOP()", "ACK STOP");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=2");
    release("RELEASE()");
}
END_TEST

/* FAST STOP disables the drive (manual 3.2.2): the part is no longer
 * clamped; after FSACK the grip is over (IDLE) but RELEASE may open the jaws */
START_TEST(faststop_while_holding_then_release)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP(20,30)", "FIN GRIP");
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    advance_ms(20);
    ASK_EQ("FORCE?", "FORCE=0.0");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=7");
    ASK_EQ("RELEASE()", "ERR RELEASE 16"); /* motion during FAST STOP */
    ASK_EQ("FSACK()", "ACK FSACK");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    advance_ms(100);
    ASK_EQ("FORCE?", "FORCE=0.0");
    ASK_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=0"); /* not a lost part: the grip was ended */
    release("RELEASE(10)");
    assert_pos(40.0f, 0.05f);
    ASK_EQ("RELEASE()", "ERR RELEASE 16");
}
END_TEST

START_TEST(dropped_connection_while_holding_then_release)
{
    place_part(30.0f, STIFF_PART_N_MM);
    h_open(&h_other, WSG_TRANSPORT_STREAM);
    ck_assert_str_eq(ask(&h_other, "GRIP(20,30)"), "ACK GRIP");
    ck_assert_str_eq(await_line(&h_other, 3000), "FIN GRIP");
    h_close(&h_other, WSG_CLOSE_DROPPED);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
    ASK_EQ("FSACK()", "ACK FSACK");
    release("RELEASE()");
}
END_TEST

START_TEST(release_only_right_after_a_grip)
{
    grip("GRIP()", "FIN GRIP");
    move_to("MOVE(60)");
    ASK_EQ("RELEASE()", "ERR RELEASE 16");
    grip("GRIP()", "FIN GRIP");
    SEND("HOME()");
    EXPECT("ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 5000), 0);
    ASK_EQ("RELEASE()", "ERR RELEASE 16");
}
END_TEST

/* --- RELEASE --- */

START_TEST(release_after_holding)
{
    place_part(30.0f, 0.0f);
    grip("GRIP()", "FIN GRIP");
    SEND("RELEASE()");
    EXPECT("ACK RELEASE");
    advance_ms(20);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=5");
    ck_assert_str_eq(await_line(&h_main, 3000), "FIN RELEASE");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
    ASK_EQ("POS?", "POS=40.0"); /* default pull back distance 10 mm */
    ASK_EQ("FORCE?", "FORCE=0.0");
}
END_TEST

START_TEST(release_forms)
{
    place_part(30.0f, 0.0f);
    grip("GRIP()", "FIN GRIP");
    release("RELEASE(5)");
    ASK_EQ("POS?", "POS=35.0");
    grip("GRIP()", "FIN GRIP");
    release("RELEASE(7.5, 50)");
    ASK_EQ("POS?", "POS=37.5");
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[2,0,0]");
}
END_TEST

START_TEST(release_is_clamped_to_the_stroke)
{
    move_to("MOVE(105)");
    place_part(100.0f, 0.0f);
    grip("GRIP()", "FIN GRIP");
    release("RELEASE(50)");
    ASK_EQ("POS?", "POS=110.0");
}
END_TEST

START_TEST(release_twice_is_denied)
{
    grip("GRIP()", "FIN GRIP");
    release("RELEASE()");
    ASK_EQ("RELEASE()", "ERR RELEASE 16");
}
END_TEST

/* --- grip monitoring --- */

START_TEST(part_removed_while_holding)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP(40, 30)", "FIN GRIP");
    wsg_sim_axis_remove_part(&h_world.axis);
    advance_ms(100);
    EXPECT_NONE(); /* no command is running: nothing to report */
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=3");
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[1,0,1]");
    ck_assert(h_log_contains(HAL_LOG_WARN, "part lost"));
    release("RELEASE()"); /* allowed from PART LOST */
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
}
END_TEST

/* A step at rest clear of every contact is taken without the integration:
 * it must still clear what the last contact left (force, blocked side, the
 * slip timer of a part pressed too weakly). */
START_TEST(part_moved_away_at_rest_leaves_no_contact)
{
    sim_axis_t axis;
    wsg_sim_axis_init(&axis, 110.0f, 2000.0f);
    wsg_sim_axis_set_part(&axis, 30.0f, STIFF_PART_N_MM, 50.0f); /* slips below 50 N */
    wsg_sim_axis_move(&axis, 0.0f, 100.0f, 1000.0f, 20.0f);
    for (int ms = 0; ms < 1000 && axis.part.squeezed_s <= 0.0f; ms++) {
        wsg_sim_axis_advance(&axis, 0.001f);
    }
    wsg_sim_axis_stop(&axis, false); /* pressed: stands at once, the outputs still set */
    ck_assert(!axis.active);
    ck_assert(axis.force_n > 0.0f);
    ck_assert_int_ne(axis.blocked, 0);
    ck_assert(axis.part.squeezed_s > 0.0f);
    wsg_sim_axis_set_part(&axis, 20.0f, STIFF_PART_N_MM, 50.0f); /* now clear of the jaws */
    wsg_sim_axis_advance(&axis, 0.0f);
    ck_assert(axis.force_n == 0.0f);
    ck_assert_int_eq(axis.blocked, 0);
    ck_assert(axis.part.squeezed_s == 0.0f);
    ck_assert(axis.part.present);
}
END_TEST

START_TEST(part_lost_is_debounced)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP(40,30)", "FIN GRIP");
    wsg_sim_axis_remove_part(&h_world.axis);
    advance_ms(5);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    advance_ms(50);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=3");
    ASK_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=1");
    advance_ms(500);
    ASK_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=1"); /* counted once */
}
END_TEST

START_TEST(gripstats_count_every_outcome)
{
    grip("GRIP()", "FIN GRIP");
    release("RELEASE()");
    grip("GRIP(40, 30)", "ERR GRIP 18");
    release("RELEASE()");
    move_to("MOVE(60)");
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP(40, 30)", "FIN GRIP");
    wsg_sim_axis_remove_part(&h_world.axis);
    advance_ms(100);
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[3,1,1]");
    ASK_EQ("GRIPSTATS[0]?", "GRIPSTATS[0]=3");
    ASK_EQ("GRIPSTATS[1]?", "GRIPSTATS[1]=1");
    ASK_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=1");
}
END_TEST

/* manual 2.2.3: Grip Monitoring only for the forms with a part width */
START_TEST(grip_without_width_is_not_monitored)
{
    place_part(30.0f, STIFF_PART_N_MM);
    grip("GRIP()", "FIN GRIP");
    wsg_sim_axis_remove_part(&h_world.axis);
    advance_ms(500);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    ASK_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=0");
    release("RELEASE(40)");
    place_part(30.0f, STIFF_PART_N_MM); /* GRIP(force) is not monitored either */
    grip("GRIP(20)", "FIN GRIP");
    wsg_sim_axis_remove_part(&h_world.axis);
    advance_ms(500);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=4");
    ASK_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=0");
}
END_TEST

START_TEST(holding_deadline)
{
    grip("GRIP()", "FIN GRIP");
    h_step();
    ck_assert_uint_le(wsg_device_next_deadline_us(&h_dev), h_now_us + 10000u);
}
END_TEST

Suite *grip_suite(void)
{
    Suite *s = suite_create("grip");
    TCase *plain = tcase_create("grip");
    tcase_add_checked_fixture(plain, h_setup_homed, h_teardown);
    tcase_add_test(plain, grip_without_part_grips_itself);
    tcase_add_test(plain, grip_part_holds_at_its_width);
    tcase_add_test(plain, grip_with_force);
    tcase_add_test(plain, grip_rigid_part);
    tcase_add_test(plain, grip_without_width_ignores_clt);
    tcase_add_test(plain, grip_while_holding_is_denied);
    tcase_add_test(plain, stop_during_grip);
    tcase_add_test(plain, stop_while_holding_keeps_the_grip);
    tcase_add_test(plain, stop_keeps_no_part);
    tcase_add_test(plain, faststop_while_holding_then_release);
    tcase_add_test(plain, dropped_connection_while_holding_then_release);
    tcase_add_test(plain, release_only_right_after_a_grip);
    suite_add_tcase(s, plain);

    TCase *width = tcase_create("part_detection");
    tcase_add_checked_fixture(width, h_setup_homed, h_teardown);
    tcase_add_test(width, grip_width_part_inside_tolerance);
    tcase_add_test(width, grip_width_part_exactly_at_width);
    tcase_add_test(width, grip_width_part_far_outside_tolerance);
    tcase_add_test(width, grip_width_without_part);
    tcase_add_test(width, grip_pwt_widens_the_band);
    tcase_add_test(width, grip_pwt_of_another_session_does_not_apply);
    tcase_add_test(width, grip_clt_limits_the_travel);
    tcase_add_test(width, grip_soft_part_beyond_clamping_travel);
    tcase_add_test(width, grip_with_speed_limit);
    tcase_add_test(width, grip_outside);
    tcase_add_test(width, grip_outside_collision);
    tcase_add_test(width, grip_outside_without_part);
    suite_add_tcase(s, width);

    TCase *rel = tcase_create("release");
    tcase_add_checked_fixture(rel, h_setup_homed, h_teardown);
    tcase_add_test(rel, release_after_holding);
    tcase_add_test(rel, release_forms);
    tcase_add_test(rel, release_is_clamped_to_the_stroke);
    tcase_add_test(rel, release_twice_is_denied);
    suite_add_tcase(s, rel);

    TCase *monitor = tcase_create("monitoring");
    tcase_add_checked_fixture(monitor, h_setup_homed, h_teardown);
    tcase_add_test(monitor, part_removed_while_holding);
    tcase_add_test(monitor, part_moved_away_at_rest_leaves_no_contact);
    tcase_add_test(monitor, part_lost_is_debounced);
    tcase_add_test(monitor, gripstats_count_every_outcome);
    tcase_add_test(monitor, grip_without_width_is_not_monitored);
    tcase_add_test(monitor, holding_deadline);
    suite_add_tcase(s, monitor);
    return s;
}
