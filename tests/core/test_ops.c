/* SPDX-License-Identifier: BSD-3-Clause */
/* The device operations API (wsg_device.h) without any protocol: immediate
 * errors, completion events to the owner, policy stated once, owners
 * detached on close, independent instances, the timer queue and the idle
 * deadline. */
#include <check.h>
#include <string.h>

#include "fake_device.h"
#include "priv/timer.h"
#include "sim/sim_models.h"
#include "unit_suites.h"

typedef struct {
    wsg_owner_t owner;
    unsigned events;
    wsg_op_t op;
    wsg_status_t status;
} probe_t;

static void probe_done(wsg_owner_t *owner, wsg_op_t op, wsg_status_t status)
{
    probe_t *p = (probe_t *)(void *)owner;
    p->events++;
    p->op = op;
    p->status = status;
}

static probe_t probe;

static void probe_setup(void)
{
    h_setup();
    memset(&probe, 0, sizeof(probe));
    probe.owner.done = probe_done;
}

/* Steps until the probe heard an event; false on timeout. */
static bool await_event(probe_t *p, uint32_t timeout_ms)
{
    for (uint32_t i = 0; i < timeout_ms && p->events == 0; i++) {
        advance_ms(1);
    }
    return p->events > 0;
}

static void home(void)
{
    wsg_home_args_t args = {WSG_HOME_DEFAULT};
    ck_assert_int_eq(wsg_op_home(&h_dev, &probe.owner, &args), E_SUCCESS);
    ck_assert(await_event(&probe, 5000));
    ck_assert_int_eq(probe.status, E_SUCCESS);
    probe.events = 0;
}

START_TEST(move_needs_a_reference)
{
    wsg_move_args_t args = {50.0f, 100.0f, false, false};
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &args), E_NOT_INITIALIZED);
    ck_assert_uint_eq(probe.events, 0);
}
END_TEST

START_TEST(home_reports_completion_to_its_owner_only_from_a_step)
{
    wsg_home_args_t args = {WSG_HOME_DEFAULT};
    ck_assert_int_eq(wsg_op_home(&h_dev, &probe.owner, &args), E_SUCCESS);
    ck_assert_uint_eq(probe.events, 0); /* never from the call that started it */
    ck_assert(await_event(&probe, 5000));
    ck_assert_uint_eq(probe.events, 1);
    ck_assert_int_eq(probe.op, WSG_OP_HOME);
    ck_assert_int_eq(probe.status, E_SUCCESS);
    ck_assert(wsg_device_snapshot(&h_dev)->referenced);
}
END_TEST

START_TEST(home_rejects_a_bad_direction)
{
    wsg_home_args_t args = {(wsg_home_dir_t)7};
    ck_assert_int_eq(wsg_op_home(&h_dev, &probe.owner, &args), E_INVALID_PARAMETER);
}
END_TEST

START_TEST(move_ranges_and_relative_target)
{
    home();
    wsg_move_args_t far = {h_cfg()->stroke_mm + 1.0f, 100.0f, false, false};
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &far), E_RANGE_ERROR);
    wsg_move_args_t slow = {50.0f, h_cfg()->speed_min_mm_s / 2.0f, false, false};
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &slow), E_RANGE_ERROR);
    float start = wsg_device_snapshot(&h_dev)->position_mm;
    wsg_move_args_t back = {-20.0f, 100.0f, true, false};
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &back), E_SUCCESS);
    ck_assert(await_event(&probe, 3000));
    ck_assert_int_eq(probe.op, WSG_OP_MOVE);
    ck_assert_int_eq(probe.status, E_SUCCESS);
    ck_assert_float_eq_tol(wsg_device_snapshot(&h_dev)->position_mm, start - 20.0f, 0.06f);
}
END_TEST

START_TEST(a_new_move_supersedes_the_running_one)
{
    home();
    probe_t other = {.owner.done = probe_done};
    wsg_move_args_t a = {10.0f, 50.0f, false, false};
    wsg_move_args_t b = {80.0f, 50.0f, false, false};
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &a), E_SUCCESS);
    advance_ms(20);
    ck_assert_int_eq(wsg_op_move(&h_dev, &other.owner, &b), E_SUCCESS);
    ck_assert_uint_eq(probe.events, 1); /* before the new one started */
    ck_assert_int_eq(probe.status, E_CMD_ABORTED);
    ck_assert(await_event(&other, 3000));
    ck_assert_int_eq(other.status, E_SUCCESS);
}
END_TEST

START_TEST(stop_aborts_with_an_event)
{
    home();
    wsg_move_args_t a = {10.0f, 50.0f, false, false};
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &a), E_SUCCESS);
    advance_ms(20);
    ck_assert_int_eq(wsg_op_stop(&h_dev), E_SUCCESS);
    ck_assert(await_event(&probe, 100));
    ck_assert_int_eq(probe.status, E_CMD_ABORTED);
    ck_assert(wsg_device_snapshot(&h_dev)->flags & WSG_FLAG(SF_AXIS_STOPPED));
}
END_TEST

START_TEST(fast_stop_denies_motion_until_acknowledged)
{
    home();
    ck_assert_int_eq(wsg_op_fast_stop(&h_dev, "test"), E_SUCCESS);
    wsg_move_args_t a = {10.0f, 50.0f, false, false};
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &a), E_ACCESS_DENIED);
    ck_assert_int_eq(wsg_op_fsack(&h_dev), E_SUCCESS);
    ck_assert_int_eq(wsg_op_move(&h_dev, &probe.owner, &a), E_SUCCESS);
}
END_TEST

START_TEST(grip_and_release_rules)
{
    home();
    wsg_release_args_t rel = {10.0f, 100.0f, false, 0.0f};
    ck_assert_int_eq(wsg_op_release(&h_dev, &probe.owner, &rel), E_ACCESS_DENIED);
    wsg_grip_args_t weak = {h_cfg()->force_min_n / 2.0f, false, 0.0f, 100.0f, 10.0f, 10.0f};
    ck_assert_int_eq(wsg_op_grip(&h_dev, &probe.owner, &weak), E_RANGE_ERROR);
    wsg_grip_args_t grip = {20.0f, false, 0.0f, 100.0f, 10.0f, 10.0f};
    ck_assert_int_eq(wsg_op_grip(&h_dev, &probe.owner, &grip), E_SUCCESS);
    ck_assert(await_event(&probe, 5000));
    ck_assert_int_eq(probe.op, WSG_OP_GRIP);
    ck_assert_int_eq(probe.status, E_SUCCESS); /* the jaws gripped themselves */
    probe.events = 0;
    wsg_release_args_t open = {0.0f, 100.0f, true, 60.0f};
    ck_assert_int_eq(wsg_op_release(&h_dev, &probe.owner, &open), E_SUCCESS);
    ck_assert(await_event(&probe, 5000));
    ck_assert_int_eq(probe.op, WSG_OP_RELEASE);
    ck_assert_float_eq_tol(wsg_device_snapshot(&h_dev)->position_mm, 60.0f, 0.06f);
}
END_TEST

START_TEST(tare_needs_a_force_finger)
{
    ck_assert_int_eq(wsg_op_tare(&h_dev, 2), E_INDEX_OUT_OF_BOUNDS);
    ck_assert_int_eq(wsg_op_tare(&h_dev, -1), E_NOT_AVAILABLE);
}
END_TEST

START_TEST(grip_stats_reset)
{
    home();
    wsg_grip_args_t grip = {20.0f, false, 0.0f, 100.0f, 10.0f, 10.0f};
    ck_assert_int_eq(wsg_op_grip(&h_dev, &probe.owner, &grip), E_SUCCESS);
    ck_assert_uint_eq(wsg_device_snapshot(&h_dev)->grip_stats[0], 1);
    ck_assert_int_eq(wsg_op_reset_grip_stats(&h_dev), E_SUCCESS);
    ck_assert_uint_eq(wsg_device_snapshot(&h_dev)->grip_stats[0], 0);
}
END_TEST

/* One max-force rule: overdrive raises the ceiling for every user. */
START_TEST(max_force_honours_overdrive_once)
{
    wsg_config_t cfg = *h_cfg();
    cfg.force_overdrive_n = 120.0f;
    cfg.overdrive_mode = false;
    ck_assert_float_eq(wsg_config_force_max(&cfg), cfg.force_max_n);
    ck_assert(!wsg_config_force_ok(&cfg, 100.0f));
    cfg.overdrive_mode = true;
    ck_assert_float_eq(wsg_config_force_max(&cfg), 120.0f);
    ck_assert(wsg_config_force_ok(&cfg, 100.0f));
    /* the device applies the same rule to its run-time settings */
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_FORCE_LIMIT, 100.0f), E_RANGE_ERROR);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_OVERDRIVE, 1.0f), E_FEATURE_NOT_SUPPORTED);
}
END_TEST

START_TEST(settings_are_device_state)
{
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_ACCEL, 1.0f), E_RANGE_ERROR);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_ACCEL, 1000.0f), E_SUCCESS);
    ck_assert_float_eq(wsg_device_snapshot(&h_dev)->config->default_accel_mm_s2, 1000.0f);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_FORCE_LIMIT, 30.0f), E_SUCCESS);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_SOFT_MINUS, 60.0f), E_SUCCESS);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_SOFT_PLUS, 50.0f), E_RANGE_ERROR);
    ck_assert_int_eq(wsg_op_set_tag(&h_dev, "cell 7", 6), E_SUCCESS);
    ASK_EQ("TAG?", "TAG=\"cell 7\"");
    char too_long[WSG_CONFIG_STRING_MAX];
    memset(too_long, 'x', sizeof(too_long));
    ck_assert_int_eq(wsg_op_set_tag(&h_dev, too_long, sizeof(too_long)), E_RANGE_ERROR);
    ck_assert_int_eq(wsg_op_set_tag(&h_dev, too_long, sizeof(too_long) - 1), E_SUCCESS);
}
END_TEST

/* A set of settings checked on a copy of the configuration, as a front end
 * checks one whole before applying any: the same rules as wsg_op_set(), in
 * order (a value allowed by one set before it), and the device untouched. */
START_TEST(settings_are_checked_on_a_copy_as_the_device_checks_them)
{
    const wsg_config_t *in_force = wsg_device_snapshot(&h_dev)->config;
    wsg_config_t trial = *in_force;
    float accel = in_force->default_accel_mm_s2;
    ck_assert_int_eq(wsg_config_setting_set(&trial, WSG_SET_ACCEL, 1.0f), E_RANGE_ERROR);
    ck_assert_int_eq(wsg_config_setting_set(&trial, WSG_SET_ACCEL, 1000.0f), E_SUCCESS);
    ck_assert_float_eq(trial.default_accel_mm_s2, 1000.0f);
    ck_assert_int_eq(wsg_config_setting_set(&trial, WSG_SET_SOFT_MINUS, 60.0f), E_SUCCESS);
    ck_assert_int_eq(wsg_config_setting_set(&trial, WSG_SET_SOFT_PLUS, 50.0f), E_RANGE_ERROR);
    ck_assert_float_eq(trial.soft_limit_plus_mm, in_force->soft_limit_plus_mm); /* kept */
    ck_assert_int_eq(wsg_config_setting_set(&trial, WSG_SET_OVERDRIVE, 1.0f),
                     wsg_op_set(&h_dev, WSG_SET_OVERDRIVE, 1.0f));
    ck_assert_int_eq(wsg_config_set_tag(&trial, "cell\n7", 6), E_INVALID_PARAMETER);
    ck_assert_int_eq(wsg_config_set_tag(&trial, "cell 7", 6), E_SUCCESS);
    ck_assert_str_eq(trial.tag, "cell 7");
    ck_assert_float_eq(in_force->default_accel_mm_s2, accel); /* the device's own: untouched */
    ck_assert_str_ne(in_force->tag, "cell 7");
}
END_TEST

/* The tag is checked once, here, for every front end: a byte
 * that could end or forge a GCL reply line is refused and the tag stays. */
START_TEST(tag_refuses_what_could_forge_a_reply)
{
    ck_assert_int_eq(wsg_op_set_tag(&h_dev, "cell-7", 6), E_SUCCESS);
    static const char *const bad[] = {"a\nFIN HOME", "a\rb",           "say \"hi\"", "tab\there",
                                      "caf\xc3\xa9", "bad \xff utf-8", "del\x7f"};
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        ck_assert_int_eq(wsg_op_set_tag(&h_dev, bad[i], strlen(bad[i])), E_INVALID_PARAMETER);
    }
    ck_assert_int_eq(wsg_op_set_tag(&h_dev, "a\0b", 3), E_INVALID_PARAMETER); /* a NUL inside */
    ASK_EQ("TAG?", "TAG=\"cell-7\"");
    const char *printable = " ~!#$%&'()*+,-./09:;<=>?@AZ[\\]^_`az{|}";
    ck_assert_int_eq(wsg_op_set_tag(&h_dev, printable, strlen(printable)), E_SUCCESS);
    ck_assert_str_eq(wsg_device_snapshot(&h_dev)->config->tag, printable);
    ck_assert_int_eq(wsg_op_set_tag(&h_dev, "", 0), E_SUCCESS);
}
END_TEST

/* The settings the web page added: the pull-back distance within
 * the stroke, the two command-interface switches. */
START_TEST(page_settings_are_device_state)
{
    const wsg_config_t *cfg = wsg_device_snapshot(&h_dev)->config;
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_DEFAULT_PULLBACK, 7.5f), E_SUCCESS);
    ck_assert_float_eq(wsg_device_snapshot(&h_dev)->config->default_pullback_mm, 7.5f);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_DEFAULT_PULLBACK, cfg->stroke_mm + 1.0f),
                     E_RANGE_ERROR);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_DEFAULT_PULLBACK, -1.0f), E_RANGE_ERROR);
    ck_assert_float_eq(wsg_device_snapshot(&h_dev)->config->default_pullback_mm, 7.5f);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_DISCONNECT_FASTSTOP, 0.0f), E_SUCCESS);
    ck_assert(!wsg_device_snapshot(&h_dev)->config->disconnect_raises_faststop);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_BINARY_CRC_CHECK, 0.0f), E_SUCCESS);
    ck_assert(wsg_device_snapshot(&h_dev)->config->bin_crc_unchecked);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_BINARY_CRC_CHECK, 1.0f), E_SUCCESS);
    ck_assert(!wsg_device_snapshot(&h_dev)->config->bin_crc_unchecked);
}
END_TEST

/* The settings' one description (wsg_setting_info): every setting reads
 * back from its own field what was stored, a switch as 0/1 whatever its
 * field holds (binary_crc_check is the opposite of bin_crc_unchecked). */
START_TEST(every_setting_reads_back_from_its_field)
{
    wsg_config_t cfg;
    wsg_sim_model_config(wsg_sim_model_default(), &cfg);
    for (int id = 0; id < WSG_SET_COUNT; id++) {
        const wsg_setting_info_t *info = wsg_setting_info((wsg_setting_t)id);
        ck_assert_ptr_nonnull(info);
        bool is_switch = info->check == WSG_SETTING_SWITCH;
        ck_assert(is_switch == (info->unit[0] == '\0')); /* a number has a unit */
        float value = is_switch ? 1.0f : 3.25f + (float)id;
        wsg_config_setting_put(&cfg, (wsg_setting_t)id, value);
        ck_assert_float_eq(wsg_config_setting_get(&cfg, (wsg_setting_t)id), value);
        if (is_switch) {
            wsg_config_setting_put(&cfg, (wsg_setting_t)id, 0.0f);
            ck_assert_float_eq(wsg_config_setting_get(&cfg, (wsg_setting_t)id), 0.0f);
        }
    }
    wsg_config_setting_put(&cfg, WSG_SET_FORCE_LIMIT, 33.0f);
    ck_assert_float_eq(cfg.default_force_n, 33.0f);
    wsg_config_setting_put(&cfg, WSG_SET_BINARY_CRC_CHECK, 1.0f);
    ck_assert(!cfg.bin_crc_unchecked);
    ck_assert_ptr_null(wsg_setting_info(WSG_SET_COUNT));
    ck_assert_float_eq(wsg_config_setting_get(&cfg, WSG_SET_COUNT), 0.0f);
    ck_assert_int_eq(wsg_op_set(&h_dev, WSG_SET_COUNT, 1.0f), E_INVALID_PARAMETER);
}
END_TEST

/* A closed connection's owner is detached: the motion's end reaches nobody,
 * not even a new connection in the same storage. */
START_TEST(owner_detached_on_close_hears_nothing)
{
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert(wsg_conn_owns_motion(&h_main.conn));
    h_close(&h_main, WSG_CLOSE_ANNOUNCED);
    ck_assert_ptr_null(wsg_device_snapshot(&h_dev)->motion_owner);
    h_open(&h_main, WSG_TRANSPORT_STREAM);
    advance_ms(3000);
    EXPECT_NONE();
    ck_assert(wsg_device_snapshot(&h_dev)->referenced);
}
END_TEST

/* Two devices in one process share nothing but the clock and the log. */
START_TEST(two_instances_are_independent)
{
    static wsg_device_t second;
    static sim_world_t second_world;
    wsg_config_t cfg;
    wsg_sim_model_config(wsg_sim_model_find("WSG 32-068"), &cfg);
    cfg.serial = 999u;
    wsg_sim_world_init(&second_world, &cfg, h_now_us);
    wsg_hal_t hal;
    wsg_sim_world_hal(&second_world, &hal);
    wsg_device_init(&second, &cfg, &hal);
    probe_t p2 = {.owner.done = probe_done};
    wsg_home_args_t args = {WSG_HOME_DEFAULT};
    ck_assert_int_eq(wsg_op_home(&second, &p2.owner, &args), E_SUCCESS);
    for (uint32_t i = 0; i < 5000 && p2.events == 0; i++) {
        h_now_us += 1000u;
        wsg_sim_world_advance(&second_world, h_now_us);
        wsg_device_step(&second);
    }
    ck_assert_int_eq(p2.status, E_SUCCESS);
    ck_assert(wsg_device_snapshot(&second)->referenced);
    ck_assert(!wsg_device_snapshot(&h_dev)->referenced); /* the first never homed */
    ck_assert_uint_eq(wsg_device_snapshot(&second)->config->serial, 999u);
    ASK_EQ("SN?", "SN=12345678");
    ck_assert_float_eq(wsg_device_snapshot(&second)->config->stroke_mm, 68.0f);
    ck_assert_float_eq(h_cfg()->stroke_mm, 110.0f);
}
END_TEST

static unsigned fired_order[4];
static unsigned fired_count;

static void record_fire(wsg_timer_t *t, uint64_t now_us)
{
    (void)now_us;
    fired_order[fired_count++] = (unsigned)(t->due_us / 10u);
}

START_TEST(timer_queue_runs_in_deadline_order)
{
    wsg_timer_queue_t q;
    wsg_timer_t t[4];
    memset(t, 0, sizeof(t));
    wsg_timer_queue_init(&q);
    ck_assert_uint_eq(wsg_timer_next_due(&q), UINT64_MAX);
    fired_count = 0;
    for (unsigned i = 0; i < 4; i++) {
        t[i].fire = record_fire;
    }
    wsg_timer_schedule(&q, &t[0], 30);
    wsg_timer_schedule(&q, &t[1], 10);
    wsg_timer_schedule(&q, &t[2], 40);
    wsg_timer_schedule(&q, &t[3], 20);
    wsg_timer_cancel(&q, &t[2]);
    ck_assert_uint_eq(wsg_timer_next_due(&q), 10);
    wsg_timer_run_due(&q, 25);
    ck_assert_uint_eq(fired_count, 2);
    ck_assert_uint_eq(fired_order[0], 1);
    ck_assert_uint_eq(fired_order[1], 2);
    ck_assert_uint_eq(wsg_timer_next_due(&q), 30);
    wsg_timer_run_due(&q, 100);
    ck_assert_uint_eq(fired_count, 3);
    ck_assert_uint_eq(wsg_timer_next_due(&q), UINT64_MAX);
}
END_TEST

START_TEST(idle_device_has_no_deadline)
{
    h_step();
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
    ASK_EQ("AUTOSEND(\"POS\",100)", "ACK AUTOSEND");
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), h_now_us);
    advance_ms(1);
    ck_assert_uint_le(wsg_device_next_deadline_us(&h_dev), h_now_us + 100000u);
    h_discard(&h_main);
    ASK_EQ("AUTOSEND(\"POS\",0)", "ACK AUTOSEND");
    h_step();
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
}
END_TEST

Suite *ops_suite(void)
{
    Suite *s = suite_create("ops");
    TCase *ops = tcase_create("operations");
    tcase_add_checked_fixture(ops, probe_setup, h_teardown);
    tcase_add_test(ops, move_needs_a_reference);
    tcase_add_test(ops, home_reports_completion_to_its_owner_only_from_a_step);
    tcase_add_test(ops, home_rejects_a_bad_direction);
    tcase_add_test(ops, move_ranges_and_relative_target);
    tcase_add_test(ops, a_new_move_supersedes_the_running_one);
    tcase_add_test(ops, stop_aborts_with_an_event);
    tcase_add_test(ops, fast_stop_denies_motion_until_acknowledged);
    tcase_add_test(ops, grip_and_release_rules);
    tcase_add_test(ops, tare_needs_a_force_finger);
    tcase_add_test(ops, grip_stats_reset);
    suite_add_tcase(s, ops);
    TCase *policy = tcase_create("policy");
    tcase_add_checked_fixture(policy, probe_setup, h_teardown);
    tcase_add_test(policy, max_force_honours_overdrive_once);
    tcase_add_test(policy, settings_are_device_state);
    tcase_add_test(policy, settings_are_checked_on_a_copy_as_the_device_checks_them);
    tcase_add_test(policy, tag_refuses_what_could_forge_a_reply);
    tcase_add_test(policy, page_settings_are_device_state);
    tcase_add_test(policy, every_setting_reads_back_from_its_field);
    suite_add_tcase(s, policy);
    TCase *inst = tcase_create("instances");
    tcase_add_checked_fixture(inst, probe_setup, h_teardown);
    tcase_add_test(inst, owner_detached_on_close_hears_nothing);
    tcase_add_test(inst, two_instances_are_independent);
    tcase_add_test(inst, timer_queue_runs_in_deadline_order);
    tcase_add_test(inst, idle_device_has_no_deadline);
    suite_add_tcase(s, inst);
    return s;
}
