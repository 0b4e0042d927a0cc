/* SPDX-License-Identifier: BSD-3-Clause */
/* The core on the loopback bus: FTYPE/FFLAGS/FDATA/TARE, force control,
 * comm-fault detection and recovery, fault injection. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can_harness.h"
#include "can_loopback.h"
#include "sim/sim_world.h"

#define FLAGS_OK "[1,1,1,0,0,0,0,0,0,0,0,0,0,0,0,0]"

static void inject(unsigned slot, uint8_t faults)
{
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, FBUS_NODE_ID(slot), faults);
    ck_assert(hal_can_send(can_loopback_bus(t_bus()), &f));
}

START_TEST(without_a_bus_the_slots_are_empty)
{
    t_start(NULL);
    t_run_ms(500);
    ck_assert_str_eq(t_ask("FTYPE?"), "FTYPE=[\"none\",\"none\"]");
    ck_assert_str_eq(t_ask("FDATA?"), "ERR FDATA 1");
    ck_assert_str_eq(t_ask("TARE()"), "ERR TARE 1");
    ck_assert_str_eq(t_ask("SYSFLAGS[9]?"), "SYSFLAGS[9]=0");
}
END_TEST

START_TEST(fingers_appear_within_50_ms)
{
    t_start("fmf,dsa");
    int ms = t_until("FTYPE?", "FTYPE=[\"fmf\",\"dsa\"]", 200);
    ck_assert_int_ge(ms, 0);
    ck_assert_int_le(ms, 50);
    t_run_ms(60);
    ck_assert_str_eq(t_ask("FFLAGS?"), "FFLAGS=[" FLAGS_OK "," FLAGS_OK "]");
    ck_assert_str_eq(t_ask("FFLAGS[1]?"), "FFLAGS[1]=" FLAGS_OK);
    ck_assert_str_eq(t_ask("FTYPE[1]?"), "FTYPE[1]=\"dsa\"");
    ck_assert_str_eq(t_ask("SYSFLAGS[9]?"), "SYSFLAGS[9]=1");
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=0");
}
END_TEST

START_TEST(empty_and_generic_slots)
{
    t_start("generic,none");
    t_run_ms(200);
    ck_assert_str_eq(t_ask("FTYPE?"), "FTYPE=[\"generic\",\"none\"]");
    ck_assert_str_eq(t_ask("FFLAGS[1]?"), "FFLAGS[1]=[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]");
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=" FLAGS_OK);
    ck_assert_str_eq(t_ask("FDATA[0]?"), "ERR FDATA 1");
    ck_assert_str_eq(t_ask("TARE()"), "ERR TARE 1");
    ck_assert_str_eq(t_ask("SYSFLAGS[9]?"), "SYSFLAGS[9]=0");
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=0");
}
END_TEST

START_TEST(fdata_fmf_offset_and_tare)
{
    t_start("fmf,dsa");
    t_run_ms(300);
    float before = t_ask_float("FDATA[0]?");
    ck_assert_float_eq_tol(before, 0.6f, 0.1f);
    ck_assert_float_eq_tol(t_ask_float("FORCE?"), before, 0.0001f); /* force control */
    ck_assert_str_eq(t_ask("TARE(1)"), "ERR TARE 1");               /* a DSA measures no force */
    ck_assert_str_eq(t_ask("TARE(2)"), "ERR TARE 25");
    ck_assert_str_eq(t_ask("TARE(0)"), "ACK TARE");
    t_run_ms(30);
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.0f, 0.08f);
    ck_assert_str_eq(t_ask("TARE()"), "ACK TARE");
}
END_TEST

START_TEST(fdata_dsa_vector_and_both)
{
    t_start("fmf,dsa");
    t_run_ms(300);
    const char *reply = t_ask("FDATA[1]?");
    ck_assert_str_eq(reply, "FDATA[1]=[0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,"
                            "0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,"
                            "0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0]");
    reply = t_ask("FDATA?");
    ck_assert_msg(strncmp(reply, "FDATA=[0.", 9) == 0, "%s", reply);
    ck_assert_msg(strstr(reply, ",[0,0,") != NULL, "%s", reply);
}
END_TEST

START_TEST(two_dsa_fingers_fit_one_reply)
{
    t_start("dsa,dsa");
    t_run_ms(300);
    h_world.axis.force_n = 0.0f;
    const char *reply = t_ask("FDATA?");
    ck_assert_msg(strncmp(reply, "FDATA=[[", 8) == 0, "%s", reply);
    ck_assert_msg(strcmp(reply + strlen(reply) - 2, "]]") == 0, "%s", reply);
}
END_TEST

/* GRIP on a 40 mm part; returns after the grip settled for settle_ms. */
static void grip_part(float force, uint32_t settle_ms)
{
    wsg_sim_axis_place_part(&h_world.axis, 40.0f, 100.0f);
    ck_assert_str_eq(t_ask("HOME()"), "ACK HOME");
    t_run_ms(3000);
    char line[32];
    snprintf(line, sizeof(line), "GRIP(%g)", (double)force);
    ck_assert_str_eq(t_ask(line), "ACK GRIP");
    t_run_ms(2000 + settle_ms);
    ck_assert_str_eq(t_ask("GRIPSTATE?"), "GRIPSTATE=4");
}

START_TEST(force_control_regulates_on_the_fmf)
{
    t_start("fmf,dsa");
    grip_part(30.0f, 1000);
    /* untared: the finger reads 0.6 N too much, so the jaws push 0.6 N less */
    ck_assert_float_eq_tol(t_ask_float("FORCE?"), 30.0f, 0.1f);
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 30.0f, 0.1f);
    ck_assert_float_eq_tol(h_world.axis.force_n, 29.4f, 0.1f);
    ck_assert_float_eq_tol(wsg_device_snapshot(&h_dev)->motor_force_n, 29.4f, 0.1f);
    ck_assert_str_eq(t_ask("SYSFLAGS[9]?"), "SYSFLAGS[9]=1");
    const char *dsa = t_ask("FDATA[1]?");
    ck_assert_msg(strstr(dsa, ",0,0,0,0,0,") != NULL && strstr(dsa, "1") != NULL, "%s", dsa);
}
END_TEST

/* The largest cell of the DSA map FDATA[1]? reads. */
static unsigned dsa_peak(void)
{
    const char *reply = t_ask("FDATA[1]?");
    const char *at = strstr(reply, "=[");
    ck_assert_msg(at != NULL, "%s", reply);
    unsigned peak = 0;
    while (at != NULL && *at != '\0' && *at != ']') {
        unsigned long cell = strtoul(at + (*at == '=' ? 2 : 1), NULL, 10);
        peak = cell > peak ? (unsigned)cell : peak;
        at = strchr(at + 1, ',');
    }
    return peak;
}

/* The fingers measure what the jaws press: when the force drops as the
 * drive goes off, the DSA map empties too, whenever in the DSA's 50 ms
 * transfer period it happens, with the FMF's force loop ending at the same
 * time or without one; the bus then sleeps again. */
START_TEST(fingers_follow_the_force_after_fast_stop)
{
    static const char *const finger_sets[] = {"fmf,dsa", "none,dsa"};
    for (unsigned set = 0; set < 2u; set++) {
        for (uint32_t phase_ms = 0; phase_ms < FBUS_BULK_PERIOD_US / 1000u; phase_ms += 5u) {
            t_start(finger_sets[set]);
            grip_part(40.0f, 500 + phase_ms);
            ck_assert_uint_gt(dsa_peak(), 1000u);
            ck_assert_str_eq(t_ask("FASTSTOP()"), "ACK FASTSTOP");
            t_run_ms(200);
            ck_assert_float_eq_tol(h_world.axis.force_n, 0.0f, 0.01f);
            ck_assert_msg(dsa_peak() == 0u, "%s, FAST STOP %u ms into the period: DSA peak %u",
                          finger_sets[set], (unsigned)phase_ms, dsa_peak());
            if (set == 0u) {
                ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.6f, 0.1f); /* its offset */
            }
            t_run_ms(1000);
            ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
        }
    }
}
END_TEST

START_TEST(tared_fmf_gives_the_true_force)
{
    t_start("fmf,none");
    t_run_ms(300);
    ck_assert_str_eq(t_ask("TARE()"), "ACK TARE");
    t_run_ms(50);
    grip_part(40.0f, 1500);
    ck_assert_float_eq_tol(h_world.axis.force_n, 40.0f, 0.1f);
    ck_assert_float_eq_tol(t_ask_float("FORCE?"), 40.0f, 0.1f);
}
END_TEST

START_TEST(comm_fault_within_timeout_and_recovery)
{
    t_start("fmf,dsa");
    t_run_ms(300);
    inject(0, FBUS_FAULT_UNPLUG);
    int ms = t_until("FFLAGS[0]?", "FFLAGS[0]=[1,1,0,0,0,0,0,0,0,1,0,0,0,0,0,0]", 1000);
    ck_assert_int_ge(ms, 280);
    ck_assert_int_le(ms, 320);
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=1");
    ck_assert_str_eq(t_ask("SYSFLAGS[9]?"), "SYSFLAGS[9]=0");
    ck_assert_str_eq(t_ask("FDATA[0]?"), "ERR FDATA 1");
    ck_assert_str_eq(t_ask("TARE()"), "ERR TARE 1");
    ck_assert_str_eq(t_ask("FTYPE?"), "FTYPE=[\"fmf\",\"dsa\"]");
    ck_assert(t_log_contains("finger 0: communication fault"));
    inject(0, 0);
    ms = t_until("FFLAGS[0]?", "FFLAGS[0]=" FLAGS_OK, 1000);
    ck_assert_int_ge(ms, 0);
    ck_assert_int_le(ms, 60);
    t_run_ms(20);
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=0");
    ck_assert_str_eq(t_ask("SYSFLAGS[9]?"), "SYSFLAGS[9]=1");
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.6f, 0.1f);
    ck_assert(t_log_contains("finger 0: communication restored"));
}
END_TEST

/* When the finger in slot 0 last sent a frame, from the bus's tap. */
static uint64_t slot0_heard_us;

static void note_slot0_frames(void *ctx, const hal_can_frame_t *frame, uint64_t time_us)
{
    (void)ctx;
    uint32_t func = fbus_func_of(frame->id);
    bool from_node = func == FBUS_ID_DESCRIPTOR || func == FBUS_ID_MEASURE ||
                     func == FBUS_ID_BULK || func == FBUS_ID_HEARTBEAT;
    if (from_node && fbus_node_of(frame->id) == FBUS_NODE_ID(0)) {
        slot0_heard_us = time_us;
    }
}

/* Every device of a fleet has a bus of its own: a fault sent on
 * another bus reaches neither this bus nor its gripper. */
START_TEST(another_bus_is_independent)
{
    fbus_type_t types[FBUS_SLOTS];
    finger_node_params_t params;
    wsg_finger_node_defaults(&params);
    ck_assert(wsg_finger_node_parse_pair("fmf,dsa", types));
    t_start("fmf,dsa");
    can_loopback_t *other = can_loopback_create(types, &params);
    ck_assert_ptr_nonnull(other);
    t_run_ms(300);
    uint32_t frames = can_loopback_frames(t_bus());
    hal_can_frame_t f;
    wsg_fbus_pack_simctl(&f, FBUS_NODE_ID(0), FBUS_FAULT_UNPLUG);
    ck_assert(hal_can_send(can_loopback_bus(other), &f));
    ck_assert_uint_eq(can_loopback_frames(other), 1);
    ck_assert_uint_eq(can_loopback_frames(t_bus()), frames);
    ck_assert_int_lt(t_until("FFLAGS[0]?", "FFLAGS[0]=[1,1,0,0,0,0,0,0,0,1,0,0,0,0,0,0]", 1000),
                     0); /* no comm fault here */
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=" FLAGS_OK);
    can_loopback_destroy(other);
}
END_TEST

/* While the jaws move the device steps every millisecond, between the
 * bus's 10 ms broadcasts: the comm fault shows at the first of those steps
 * past the timeout, not at the next broadcast. */
START_TEST(comm_fault_at_its_step_between_broadcasts)
{
    t_start("fmf,dsa");
    can_loopback_set_tap(t_bus(), note_slot0_frames, NULL);
    t_run_ms(300);
    ck_assert_str_eq(t_ask("HOME()"), "ACK HOME");
    t_run_ms(50);
    inject(0, FBUS_FAULT_UNPLUG);
    int ms = t_until("FFLAGS[0]?", "FFLAGS[0]=[1,1,0,0,0,0,0,0,0,1,0,0,0,0,0,0]", 1000);
    can_loopback_set_tap(t_bus(), NULL, NULL);
    ck_assert_int_ge(ms, 0);
    ck_assert_str_eq(t_ask("SYSFLAGS[1]?"), "SYSFLAGS[1]=1"); /* still moving */
    ck_assert_uint_eq(h_now_us, slot0_heard_us + FBUS_COMM_TIMEOUT_US + 1000u);
}
END_TEST

START_TEST(power_and_init_faults)
{
    t_start("fmf,dsa");
    t_run_ms(300);
    inject(1, FBUS_FAULT_POWER);
    ck_assert_int_ge(t_until("FFLAGS[1]?", "FFLAGS[1]=[1,1,1,0,0,0,0,0,1,0,0,0,0,0,0,0]", 200), 0);
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=1");
    ck_assert_str_eq(t_ask("FDATA[1]?"), "ERR FDATA 1");
    inject(1, 0);
    ck_assert_int_ge(t_until("FFLAGS[1]?", "FFLAGS[1]=" FLAGS_OK, 200), 0);
    ck_assert_int_ge(t_until("SYSFLAGS[17]?", "SYSFLAGS[17]=0", 50), 0);
    t_run_ms(100);
    const char *dsa = t_ask("FDATA[1]?");
    ck_assert_msg(strncmp(dsa, "FDATA[1]=[0,0,", 14) == 0, "%s", dsa);
    inject(0, FBUS_FAULT_INIT);
    ck_assert_int_ge(t_until("FFLAGS[0]?", "FFLAGS[0]=[1,1,1,0,0,0,0,0,0,0,1,0,0,0,0,0]", 200), 0);
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=1");
    ck_assert_str_eq(t_ask("SYSFLAGS[9]?"), "SYSFLAGS[9]=0");
}
END_TEST

START_TEST(init_fault_at_power_on_has_no_config)
{
    t_start("fmf,dsa");
    inject(0, FBUS_FAULT_INIT);
    t_run_ms(300);
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=[1,0,1,0,0,0,0,0,0,0,1,0,0,0,0,0]");
    ck_assert_str_eq(t_ask("FTYPE[0]?"), "FTYPE[0]=\"none\"");
    inject(0, 0);
    ck_assert_int_ge(t_until("FTYPE[0]?", "FTYPE[0]=\"fmf\"", 200), 0);
}
END_TEST

/* A finger that boots again (unplugged and plugged back, too briefly for a
 * comm fault) is forgotten until it describes itself again: no
 * configuration, no type in between. */
START_TEST(rebooted_finger_has_no_config_until_described)
{
    t_start("fmf,dsa");
    t_run_ms(300);
    inject(1, FBUS_FAULT_UNPLUG);
    t_run_ms(50);
    ck_assert_str_eq(t_ask("FTYPE[1]?"), "FTYPE[1]=\"dsa\"");
    inject(1, 0);
    ck_assert_int_ge(t_until("FTYPE[1]?", "FTYPE[1]=\"none\"", 30), 0);
    ck_assert_str_eq(t_ask("FFLAGS[1]?"), "FFLAGS[1]=[1,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0]");
    ck_assert_int_ge(t_until("FTYPE[1]?", "FTYPE[1]=\"dsa\"", 100), 0);
    ck_assert_str_eq(t_ask("FFLAGS[1]?"), "FFLAGS[1]=" FLAGS_OK);
}
END_TEST

START_TEST(clock_jumps_keep_loopback_fingers)
{
    t_start("fmf,dsa");
    t_run_ms(300);
    ck_assert_str_eq(t_ask("TARE()"), "ACK TARE");
    t_run_ms(50);
    for (int i = 0; i < 3; i++) {
        h_now_us += 5000000u; /* a paused clock stepped by 5 s */
        wsg_sim_world_advance(&h_world, h_now_us);
        wsg_device_step(&h_dev);
        ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=" FLAGS_OK);
    }
    t_run_ms(20);
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.0f, 0.08f); /* still tared */
    ck_assert_uint_eq(h_devp()->fbus.comm_faults, 0);
}
END_TEST

/* The rates of a real bus; the in-process bus keeps them while it ticks
 * (here: the settling after power-on). */
START_TEST(bus_frame_rates)
{
    t_start("fmf,dsa");
    t_run_ms(100);
    uint32_t before = can_loopback_frames(t_bus());
    uint32_t tx = h_devp()->fbus.tx_frames;
    t_run_ms(300);
    ck_assert_uint_ge(h_devp()->fbus.tx_frames - tx, 29);
    ck_assert_uint_le(h_devp()->fbus.tx_frames - tx, 31);
    /* 30 STATE + 30 MEASURE + 6 x 28 BULK + 6 heartbeats */
    uint32_t frames = can_loopback_frames(t_bus()) - before;
    ck_assert_uint_ge(frames, 224);
    ck_assert_uint_le(frames, 244);
}
END_TEST

/* An idle device on the in-process bus has nothing due,
 * and the fingers are as they were when it next steps. */
START_TEST(idle_bus_sleeps_and_wakes_intact)
{
    t_start("fmf,dsa");
    t_run_ms(1000);
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
    uint32_t frames = can_loopback_frames(t_bus());
    h_now_us += 10000000u; /* 10 s with nothing due: nobody steps the device */
    wsg_sim_world_advance(&h_world, h_now_us);
    ck_assert_uint_eq(can_loopback_frames(t_bus()) - frames, 0);
    ck_assert_str_eq(t_ask("FFLAGS?"), "FFLAGS=[" FLAGS_OK "," FLAGS_OK "]");
    wsg_device_step(&h_dev); /* a command's step: a whole bus cycle at this instant */
    ck_assert_uint_gt(can_loopback_frames(t_bus()) - frames, 0);
    ck_assert_str_eq(t_ask("FFLAGS?"), "FFLAGS=[" FLAGS_OK "," FLAGS_OK "]");
    ck_assert_str_eq(t_ask("FTYPE?"), "FTYPE=[\"fmf\",\"dsa\"]");
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.6f, 0.1f);
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=0");
    ck_assert_uint_eq(h_devp()->fbus.comm_faults, 0);
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
}
END_TEST

/* TARE and a fault injection wake the idle bus until they took effect. */
START_TEST(idle_bus_wakes_for_tare_and_faults)
{
    t_start("fmf,dsa");
    t_run_ms(1000);
    ck_assert_str_eq(t_ask("TARE()"), "ACK TARE");
    ck_assert_uint_lt(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
    t_run_ms(30);
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.0f, 0.08f);
    t_run_ms(1000);
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
    t_run_ms(1); /* the host steps the device before it injects (finger_bus_host.c) */
    inject(0, FBUS_FAULT_UNPLUG);
    t_run_ms(250);
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=" FLAGS_OK);
    t_run_ms(100);
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=[1,1,0,0,0,0,0,0,0,1,0,0,0,0,0,0]");
    ck_assert_str_eq(t_ask("SYSFLAGS[17]?"), "SYSFLAGS[17]=1");
}
END_TEST

/* Fingers that have settled, on a bus losing the first `lost` TAREs; then
 * the TARE line. */
static void tare_on_lossy_bus(unsigned lost, const char *line)
{
    t_start_losing_tares("fmf,dsa", lost);
    t_run_ms(300);
    ck_assert_str_eq(t_ask(line), "ACK TARE");
}

/* A TARE the finger never took (its receive queue was full) is sent again
 * until the finger's MEASURE frames count it. */
START_TEST(lost_tare_is_sent_again)
{
    tare_on_lossy_bus(1, "TARE()");
    t_run_ms(30);
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.6f, 0.1f); /* the first one was lost */
    t_run_ms(FBUS_TARE_RETRY_US / 1000u + 30u);
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.0f, 0.08f);
    ck_assert_uint_eq(t_tares_sent(), 2);
    t_run_ms(1000);
    ck_assert_uint_eq(t_tares_sent(), 2); /* counted: no more repeats */
    ck_assert(!t_log_contains("TARE not confirmed"));
}
END_TEST

/* The wait for the count starts at the step after TARE(), not at the last
 * step of a bus that slept: no repeat at once. */
START_TEST(tare_on_a_sleeping_bus_waits_before_repeating)
{
    t_start_losing_tares("fmf,dsa", 1);
    t_run_ms(2000);
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX); /* asleep */
    ck_assert_str_eq(t_ask("TARE()"), "ACK TARE");
    t_run_ms(FBUS_TARE_RETRY_US / 1000u - 20u);
    ck_assert_uint_eq(t_tares_sent(), 1);
    t_run_ms(40);
    ck_assert_uint_eq(t_tares_sent(), 2);
}
END_TEST

START_TEST(confirmed_tare_is_sent_once)
{
    tare_on_lossy_bus(0, "TARE(0)");
    t_run_ms(1000);
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.0f, 0.08f);
    ck_assert_uint_eq(t_tares_sent(), 1);
}
END_TEST

/* A finger that never counts the TARE gets a bounded number of them, and
 * the log says so; the bus then goes back to sleep. */
START_TEST(unconfirmed_tare_gives_up)
{
    tare_on_lossy_bus(100, "TARE()");
    t_run_ms(2000);
    ck_assert_uint_eq(t_tares_sent(), FBUS_TARE_SENDS);
    ck_assert(t_log_contains("finger 0: TARE not confirmed by the finger"));
    ck_assert_float_eq_tol(t_ask_float("FDATA[0]?"), 0.6f, 0.1f);
    ck_assert_uint_eq(wsg_device_next_deadline_us(&h_dev), UINT64_MAX);
}
END_TEST

/* On a bus that runs on its own (SocketCAN), fingers silent while the
 * gripper runs are faulted in 300-310 ms, and recover with their next frame. */
START_TEST(held_fingers_on_a_running_gripper_are_faulted)
{
    t_start_real_time("fmf,dsa");
    t_run_ms(300);
    t_hold_fingers(true);
    t_run_ms(290);
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=" FLAGS_OK);
    t_run_ms(30);
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=[1,1,0,0,0,0,0,0,0,1,0,0,0,0,0,0]");
    t_hold_fingers(false);
    t_run_ms(50);
    ck_assert_str_eq(t_ask("FFLAGS[0]?"), "FFLAGS[0]=" FLAGS_OK);
}
END_TEST

/* The frames a tapped loopback carried, at device times from the start. */
#define SEEN_MAX 16384u
typedef struct {
    hal_can_frame_t frames[SEEN_MAX];
    uint64_t at_us[SEEN_MAX];
    unsigned count;
    uint64_t start_us;
} seen_t;
static seen_t seen_skipping, seen_polling;

static void see(void *ctx, const hal_can_frame_t *frame, uint64_t time_us)
{
    seen_t *seen = ctx;
    ck_assert_uint_lt(seen->count, SEEN_MAX);
    seen->frames[seen->count] = *frame;
    seen->at_us[seen->count] = time_us - seen->start_us;
    seen->count++;
}

/* Moves, a grip under force control, TARE, an injected fault, a bus that
 * sleeps and wakes, with every frame on the bus seen. */
static void run_seen(seen_t *seen)
{
    seen->count = 0;
    seen->start_us = h_now_us;
    can_loopback_set_tap(t_bus(), see, seen);
    t_run_ms(300);
    ck_assert_str_eq(t_ask("TARE()"), "ACK TARE");
    t_run_ms(50);
    grip_part(30.0f, 1000);
    ck_assert_str_eq(t_ask("RELEASE(10)"), "ACK RELEASE");
    t_run_ms(700);
    inject(1, FBUS_FAULT_INIT);
    t_run_ms(400);
    inject(1, 0);
    t_run_ms(1500); /* the bus sleeps: the device is not stepped */
    ck_assert_str_eq(t_ask("MOVE(60)"), "ACK MOVE");
    t_run_ms(1500);
    can_loopback_set_tap(t_bus(), NULL, NULL);
}

/* The core skips the polls the loopback says would find nothing
 * (hal_can_quiet_until_us): the bus carries the frames, at the times, of a
 * core that polls at every step (the same loopback behind a wrapper that
 * keeps no quiet time). */
START_TEST(skipped_quiet_polls_change_no_frame)
{
    t_start("fmf,dsa");
    run_seen(&seen_skipping);
    t_start_losing_tares("fmf,dsa", 0);
    run_seen(&seen_polling);
    ck_assert_uint_gt(seen_polling.count, 3000u);
    ck_assert_uint_eq(seen_skipping.count, seen_polling.count);
    for (unsigned i = 0; i < seen_polling.count; i++) {
        const hal_can_frame_t *a = &seen_skipping.frames[i];
        const hal_can_frame_t *b = &seen_polling.frames[i];
        ck_assert_msg(seen_skipping.at_us[i] == seen_polling.at_us[i] && a->id == b->id &&
                          a->dlc == b->dlc && memcmp(a->data, b->data, sizeof(a->data)) == 0,
                      "frame %u: 0x%03x at %llu us, polling 0x%03x at %llu us", i, (unsigned)a->id,
                      (unsigned long long)seen_skipping.at_us[i], (unsigned)b->id,
                      (unsigned long long)seen_polling.at_us[i]);
    }
}
END_TEST

/* A device step at every ms; whether it polled the bus. When a poll
 * follows skipped ones, the core told the bus the last skipped step's time
 * first (the nodes' stall bookkeeping counts polls). */
static bool step_polled(uint64_t *last_step_us, bool *skipped_before)
{
    h_now_us += 1000u;
    wsg_sim_world_advance(&h_world, h_now_us);
    unsigned polls = t_polls();
    uint64_t told_us;
    unsigned told = t_skips_told(&told_us);
    wsg_device_step(&h_dev);
    bool polled = t_polls() != polls;
    unsigned told_now = t_skips_told(&told_us);
    if (polled && *skipped_before) {
        ck_assert_uint_eq(told_now, told + 1u);
        ck_assert_uint_eq(told_us, *last_step_us);
    } else {
        ck_assert_uint_eq(told_now, told);
    }
    *skipped_before = !polled;
    *last_step_us = h_now_us;
    return polled;
}

/* While the jaws move the core skips most polls (nine in ten steps take no
 * frame), tells the bus the last one skipped before it polls again, and
 * polls at the step after a TARE() between steps. */
START_TEST(quiet_steps_skip_the_poll_and_tell_it)
{
    t_start_counting_polls("fmf,dsa");
    t_run_ms(300);
    ck_assert_str_eq(t_ask("HOME()"), "ACK HOME");
    uint64_t last_step_us = h_now_us;
    bool skipped_before = false;
    unsigned skipped = 0;
    for (unsigned ms = 0; ms < 200u; ms++) {
        skipped += step_polled(&last_step_us, &skipped_before) ? 0u : 1u;
    }
    ck_assert_uint_ge(skipped, 150u);
    while (step_polled(&last_step_us, &skipped_before)) {
    }
    ck_assert_str_eq(t_ask("TARE()"), "ACK TARE");
    ck_assert(step_polled(&last_step_us, &skipped_before));
}
END_TEST

Suite *bus_suite(void)
{
    Suite *s = suite_create("finger bus in the core");
    TCase *tc = tcase_create("bus");
    tcase_set_timeout(tc, 30);
    tcase_add_test(tc, without_a_bus_the_slots_are_empty);
    tcase_add_test(tc, fingers_appear_within_50_ms);
    tcase_add_test(tc, empty_and_generic_slots);
    tcase_add_test(tc, fdata_fmf_offset_and_tare);
    tcase_add_test(tc, fdata_dsa_vector_and_both);
    tcase_add_test(tc, two_dsa_fingers_fit_one_reply);
    tcase_add_test(tc, force_control_regulates_on_the_fmf);
    tcase_add_test(tc, tared_fmf_gives_the_true_force);
    tcase_add_test(tc, fingers_follow_the_force_after_fast_stop);
    tcase_add_test(tc, comm_fault_within_timeout_and_recovery);
    tcase_add_test(tc, comm_fault_at_its_step_between_broadcasts);
    tcase_add_test(tc, power_and_init_faults);
    tcase_add_test(tc, init_fault_at_power_on_has_no_config);
    tcase_add_test(tc, rebooted_finger_has_no_config_until_described);
    tcase_add_test(tc, clock_jumps_keep_loopback_fingers);
    tcase_add_test(tc, bus_frame_rates);
    tcase_add_test(tc, idle_bus_sleeps_and_wakes_intact);
    tcase_add_test(tc, idle_bus_wakes_for_tare_and_faults);
    tcase_add_test(tc, lost_tare_is_sent_again);
    tcase_add_test(tc, confirmed_tare_is_sent_once);
    tcase_add_test(tc, tare_on_a_sleeping_bus_waits_before_repeating);
    tcase_add_test(tc, unconfirmed_tare_gives_up);
    tcase_add_test(tc, held_fingers_on_a_running_gripper_are_faulted);
    tcase_add_test(tc, another_bus_is_independent);
    tcase_add_test(tc, skipped_quiet_polls_change_no_frame);
    tcase_add_test(tc, quiet_steps_skip_the_poll_and_tell_it);
    suite_add_tcase(s, tc);
    return s;
}
