/* SPDX-License-Identifier: BSD-3-Clause */
/* Every command and syntax form of the manual, with the exact reply lines. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include "fake_device.h"
#include "wsg/wsg_inject.h"
#include "wsg/wsg_textbuf.h"
#include "unit_suites.h"

/* "[b0,b1,...]" for `count` bits of `bits`. */
static const char *bits_text(uint32_t bits, unsigned count)
{
    static char text[80];
    size_t n = 0;
    text[n++] = '[';
    for (unsigned i = 0; i < count; i++) {
        if (i > 0) {
            text[n++] = ',';
        }
        text[n++] = ((bits >> i) & 1u) != 0u ? '1' : '0';
    }
    text[n++] = ']';
    text[n] = '\0';
    return text;
}

static void ask_prefixed(const char *line, const char *prefix, const char *body)
{
    char expected[256];
    snprintf(expected, sizeof(expected), "%s%s", prefix, body);
    ASK_EQ(line, expected);
}

/* --- interface control --- */

START_TEST(verbose_set_and_reply)
{
    ASK_EQ("VERBOSE=1", "VERBOSE=1");
    ASK_EQ("VERBOSE=0", "VERBOSE=0");
    ASK_EQ("verbose=1", "VERBOSE=1");
    ASK_EQ("VERBOSE = 0", "VERBOSE=0");
    ASK_EQ("VERBOSE=true", "VERBOSE=1"); /* tolerated spellings */
    ASK_EQ("VERBOSE=0.0", "VERBOSE=0");
}
END_TEST

START_TEST(verbose_query_is_tolerated)
{
    ASK_EQ("VERBOSE?", "VERBOSE=0");
    ASK_EQ("VERBOSE=1", "VERBOSE=1");
    ASK_EQ("VERBOSE?", "VERBOSE=1");
}
END_TEST

/* --- system commands --- */

START_TEST(identity)
{
    ASK_EQ("DEVTYPE?", "DEVTYPE=\"WSG 50-110\"");
    ASK_EQ("VERSION?", "VERSION=\"4.0.0\"");
    ASK_EQ("SN?", "SN=12345678");
    ASK_EQ("TAG?", "TAG=\"wsgsim\"");
}
END_TEST

START_TEST(lower_case_commands_answer_upper_case)
{
    ASK_EQ("devtype?", "DEVTYPE=\"WSG 50-110\"");
    ASK_EQ("sN?", "SN=12345678");
    ASK_EQ("gripStats[0]?", "GRIPSTATS[0]=0");
}
END_TEST

START_TEST(temperature)
{
    /* ambient 25 C plus the idle rise of the thermal model */
    ASK_EQ("TEMP?", "TEMP=34.0");
    advance_ms(100);
    ASK_EQ("TEMP?", "TEMP=34.0");
}
END_TEST

/* Queries pipelined in one input share a reading while the clock stands;
 * what acts on the device, within the input or between inputs, is seen. */
START_TEST(pipelined_queries_see_a_command_at_the_same_instant)
{
    static const char lines[] = "SYSFLAGS[1]?\nMOVE(20)\nSYSFLAGS[1]?\n";
    h_send_bytes(&h_main, lines, sizeof(lines) - 1);
    EXPECT("SYSFLAGS[1]=0");
    EXPECT("ACK MOVE");
    EXPECT("SYSFLAGS[1]=1");
    EXPECT_NONE();
}
END_TEST

START_TEST(pipelined_queries_see_the_world_change_between_inputs)
{
    static const char lines[] = "TEMP?\nTEMP?\n";
    h_send_bytes(&h_main, lines, sizeof(lines) - 1);
    EXPECT("TEMP=34.0");
    EXPECT("TEMP=34.0");
    h_world.thermal.override_c = 50.0f; /* the clock stands */
    h_send_bytes(&h_main, lines, sizeof(lines) - 1);
    EXPECT("TEMP=50.0");
    EXPECT("TEMP=50.0");
    EXPECT_NONE();
}
END_TEST

/* A float reply reuses its connection's kept text only for the same value,
 * bit for bit: each reply is the rule's text, whether the value repeats,
 * returns after another, differs only in its sign bit, or has a text too
 * long to keep. */
START_TEST(float_replies_kept_or_formatted_are_the_rule_s_text)
{
    /* above absolute zero: the thermal model's override */
    static const float values[] = {34.0f,       34.0f,     34.001f,   34.0f,     0.0f,
                                   -0.0f,       0.0f,      -272.125f, -272.125f, 1.0f / 3.0f,
                                   1.0f / 3.0f, 1.0e9f,    1.0e9f,    33.25f,    12345678.0f,
                                   12345678.0f, 99999.99f, 0.0005f,   0.0004f,   0.0005f};
    for (size_t i = 0; i < sizeof(values) / sizeof(values[0]); i++) {
        h_world.thermal.override_c = values[i];
        advance_ms(1); /* a sense at a new instant */
        char expected[64] = "TEMP=";
        expected[5 + wsg_textbuf_format_float(expected + 5, values[i])] = '\0';
        ck_assert_str_eq(ask(&h_main, "TEMP?"), expected);
    }
}
END_TEST

/* A repeated query line is answered as the first was; a line with other
 * bytes, even of the same length or with the same text left once a bad
 * byte is dropped, is parsed for itself. */
START_TEST(repeated_query_lines_are_each_answered_for_their_own_bytes)
{
    static const char lines[] = "POS?\nPOS?\nTAG?\npos?\nPOS?\n POS ?\nPOS?\nPOS\x01?\nPOS?\n";
    h_send_bytes(&h_main, lines, sizeof(lines) - 1);
    EXPECT("POS=55.0");
    EXPECT("POS=55.0");
    EXPECT("TAG=\"wsgsim\"");
    EXPECT("POS=55.0");
    EXPECT("POS=55.0");
    EXPECT("POS=55.0");
    EXPECT("POS=55.0");
    EXPECT("ERR POS 15"); /* E_CMD_FORMAT_ERROR */
    EXPECT("POS=55.0");
    EXPECT_NONE();
}
END_TEST

/* --- a repeated query line answers as its parse did --- */

/* What the GCL observer heard of the last command line. */
typedef struct {
    char name[WSG_GCL_NAME_MAX + 1];
    int index;
    unsigned form;
    unsigned argc;
    wsg_status_t status;
    unsigned count;
} heard_t;

static heard_t heard;

static void on_command_done(void *ctx, const wsg_conn_t *c, const char *name, int index,
                            unsigned form, unsigned argc, wsg_status_t status)
{
    (void)ctx;
    (void)c;
    snprintf(heard.name, sizeof(heard.name), "%s", name);
    heard.index = index;
    heard.form = form;
    heard.argc = argc;
    heard.status = status;
    heard.count++;
}

/* Everything one line leaves behind: its reply, the command event, the
 * connection's and the device's SF_CMD_FAILURE, the line counts. */
typedef struct {
    char reply[H_LINE_LEN];
    heard_t heard;
    bool conn_failed;
    bool device_failed;
    uint32_t lines_in;
    uint32_t lines_out;
} outcome_t;

static outcome_t outcome_of(const char *bytes)
{
    outcome_t o;
    memset(&o, 0, sizeof(o));
    memset(&heard, 0, sizeof(heard));
    uint32_t in = h_gcl_lines_in(&h_main);
    uint32_t out = h_gcl_lines_out(&h_main);
    h_send_bytes(&h_main, bytes, strlen(bytes));
    snprintf(o.reply, sizeof(o.reply), "%s", h_next_line(&h_main));
    ck_assert_msg(h_unread(&h_main) == 0, "\"%s\" gave more than one line", bytes);
    o.heard = heard;
    wsg_gcl_conn_info_t info;
    ck_assert(wsg_gcl_conn_info(&h_main.conn, &info));
    o.conn_failed = info.cmd_failed;
    o.device_failed = (wsg_device_flags(&h_dev) & WSG_FLAG(SF_CMD_FAILURE)) != 0u;
    o.lines_in = h_gcl_lines_in(&h_main) - in;
    o.lines_out = h_gcl_lines_out(&h_main) - out;
    return o;
}

static void expect_same_outcome(const outcome_t *a, const outcome_t *b, const char *line)
{
    ck_assert_msg(strcmp(a->reply, b->reply) == 0, "%s: \"%s\" then \"%s\"", line, a->reply,
                  b->reply);
    ck_assert_msg(memcmp(&a->heard, &b->heard, sizeof(a->heard)) == 0, "%s: events differ", line);
    ck_assert_msg(a->conn_failed == b->conn_failed && a->device_failed == b->device_failed,
                  "%s: SF_CMD_FAILURE differs", line);
    ck_assert_uint_eq(a->lines_in, b->lines_in);
    ck_assert_uint_eq(a->lines_out, b->lines_out);
}

static void send_text(const char *text)
{
    h_send_bytes(&h_main, text, strlen(text));
    h_discard(&h_main);
}

/* A line as the drivers send it, parsed, then repeated: a plain query's
 * repeat is not parsed (the dispatcher remembers the line). Each runs after
 * the same line before it (a success, or a failure that SF_CMD_FAILURE
 * shows), ended by "\n", "\r" or "\r\n": the outcome must not tell them
 * apart. Another query before the parsed one makes it forget the line. */
static void expect_repeats_answer_as_first(const char *line)
{
    static const char *const before[] = {"SN?\n", "NOSUCH?\n"};
    static const char *const ends[] = {"\n", "\r", "\r\n"};
    char bytes[64];
    char remember[64];
    snprintf(remember, sizeof(remember), "%s\n", line);
    for (size_t b = 0; b < sizeof(before) / sizeof(before[0]); b++) {
        for (size_t e = 0; e < sizeof(ends) / sizeof(ends[0]); e++) {
            snprintf(bytes, sizeof(bytes), "%s%s", line, ends[e]);
            send_text("TAG?\n");
            send_text(before[b]);
            outcome_t parsed = outcome_of(bytes);
            send_text(remember);
            send_text(before[b]);
            outcome_t repeated = outcome_of(bytes);
            expect_same_outcome(&parsed, &repeated, line);
        }
    }
}

/* The spellings drivers send: every query of the table, in lower case,
 * with spaces and tabs, and the forms a query's name does not allow. */
static const char *const repeat_lines[] = {
    "POS?",
    "pos?",
    " POS?",
    "POS ?",
    "\tPoS\t?  ",
    "SPEED?",
    "speed?",
    "FORCE?",
    "GRIPSTATE?",
    "gripstate?",
    "DEVTYPE?",
    "VERSION?",
    "SN?",
    "TAG?",
    "TEMP?",
    "PWT?",
    "clt ?",
    "VERBOSE?",
    "SYSFLAGS?",
    "MOVE?",
    "HOME?",
    "GRIPSTATS?",
    "FDATA?",
    "NOSUCH?",
    "POS??",
    "PWT=50",
    "pwt = 50.00",
    "CLT=20.000000",
    "SYSFLAGS[1]?",
    "MOVE(50)",
    "MOVE(50.00, 20.000000)",
    "VERBOSE=0",
    "POSITION?",
    "P?",
    "A_VERY_LONG_NAME?",
};

START_TEST(repeated_query_lines_answer_as_their_parse)
{
    for (size_t i = 0; i < sizeof(repeat_lines) / sizeof(repeat_lines[0]); i++) {
        expect_repeats_answer_as_first(repeat_lines[i]);
    }
}
END_TEST

/* The same, watched: with a GCL observer the command events must match too. */
START_TEST(repeated_query_lines_report_as_their_parse)
{
    wsg_gcl_observer_t observer = {.command_done = on_command_done};
    wsg_gcl_add_observer(&h_dev, &observer);
    for (size_t i = 0; i < sizeof(repeat_lines) / sizeof(repeat_lines[0]); i++) {
        expect_repeats_answer_as_first(repeat_lines[i]);
        ck_assert_uint_eq(heard.count, 1u); /* the last line was heard, once */
    }
    wsg_gcl_remove_observer(&h_dev, &observer);
}
END_TEST

/* A failure the simulation injects answers a repeated query too, once. */
START_TEST(repeated_query_meets_an_injected_failure)
{
    ASK_EQ("POS?", "POS=55.0");
    ASK_EQ("POS?", "POS=55.0");
    wsg_device_inject_failure(&h_dev, "POS", E_CMD_FAILED);
    ASK_EQ("POS?", "ERR POS 18");
    ck_assert(wsg_device_flags(&h_dev) & WSG_FLAG(SF_CMD_FAILURE));
    ASK_EQ("POS?", "POS=55.0");
    ck_assert(!(wsg_device_flags(&h_dev) & WSG_FLAG(SF_CMD_FAILURE)));
}
END_TEST

START_TEST(sysflags_at_power_on)
{
    ask_prefixed("SYSFLAGS?", "SYSFLAGS=", bits_text(0u, 32));
    ASK_EQ("SYSFLAGS[0]?", "SYSFLAGS[0]=0");
    ASK_EQ("SYSFLAGS[31]?", "SYSFLAGS[31]=0");
}
END_TEST

/* --- gripper state --- */

START_TEST(state_at_power_on)
{
    ASK_EQ("POS?", "POS=55.0"); /* mid-stroke until homed */
    ASK_EQ("SPEED?", "SPEED=0.0");
    ASK_EQ("FORCE?", "FORCE=0.0");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
}
END_TEST

START_TEST(gripstats_forms)
{
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[0,0,0]");
    ASK_EQ("GRIPSTATS[0]?", "GRIPSTATS[0]=0");
    ASK_EQ("GRIPSTATS[1]?", "GRIPSTATS[1]=0");
    ASK_EQ("GRIPSTATS[2]?", "GRIPSTATS[2]=0");
}
END_TEST

START_TEST(pwt_and_clt_defaults)
{
    ASK_EQ("PWT?", "PWT=10.0");
    ASK_EQ("CLT?", "CLT=10.0");
}
END_TEST

START_TEST(pwt_and_clt_set)
{
    ASK_EQ("PWT=2.5", "PWT=2.5");
    ASK_EQ("PWT?", "PWT=2.5");
    ASK_EQ("CLT=0.125", "CLT=0.125");
    ASK_EQ("CLT?", "CLT=0.125");
    ASK_EQ("PWT=0", "PWT=0.0");
    ASK_EQ("CLT=110", "CLT=110.0");
    ASK_EQ("PWT?", "PWT=0.0");
}
END_TEST

/* --- finger interface --- */

START_TEST(fingers_without_fingers)
{
    ASK_EQ("FTYPE?", "FTYPE=[\"none\",\"none\"]");
    ASK_EQ("FTYPE[0]?", "FTYPE[0]=\"none\"");
    ASK_EQ("FTYPE[1]?", "FTYPE[1]=\"none\"");
    const char *zero = bits_text(0u, 16);
    char expected[128];
    snprintf(expected, sizeof(expected), "FFLAGS=[%s,%s]", zero, zero);
    ASK_EQ("FFLAGS?", expected);
    ask_prefixed("FFLAGS[1]?", "FFLAGS[1]=", zero);
    ASK_EQ("FDATA?", "ERR FDATA 1");
    ASK_EQ("FDATA[0]?", "ERR FDATA 1");
    ASK_EQ("TARE()", "ERR TARE 1");
}
END_TEST

static void install_fmf_finger(void)
{
    wsg_finger_t *f = &h_devp()->fingers.slot[0];
    f->type = FINGER_FMF;
    f->flags =
        (uint16_t)(WSG_FLAG(FF_POWER_ON) | WSG_FLAG(FF_CONFIG_AVAIL) | WSG_FLAG(FF_COMM_OPEN));
    f->data_count = 1;
    f->data[0] = 12.5f;
}

START_TEST(fingers_with_force_finger)
{
    install_fmf_finger();
    ASK_EQ("FTYPE?", "FTYPE=[\"fmf\",\"none\"]");
    ASK_EQ("FTYPE[0]?", "FTYPE[0]=\"fmf\"");
    ask_prefixed("FFLAGS[0]?", "FFLAGS[0]=", bits_text(0x7u, 16));
    ASK_EQ("FDATA?", "FDATA=[12.5,[]]");
    ASK_EQ("FDATA[0]?", "FDATA[0]=12.5");
    ASK_EQ("FDATA[1]?", "ERR FDATA 1");
}
END_TEST

START_TEST(tare_forms)
{
    install_fmf_finger();
    ASK_EQ("TARE()", "ACK TARE");
    ASK_EQ("TARE(0)", "ACK TARE");
    ASK_EQ("TARE(1)", "ERR TARE 1");
}
END_TEST

START_TEST(fdata_of_tactile_finger)
{
    wsg_finger_t *f = &h_devp()->fingers.slot[1];
    f->type = FINGER_DSA;
    f->data_count = 3;
    f->data[0] = 1.0f;
    f->data[1] = 4095.0f;
    f->data[2] = 0.0f;
    ASK_EQ("FTYPE[1]?", "FTYPE[1]=\"dsa\"");
    /* tactile cells are raw integers */
    ASK_EQ("FDATA[1]?", "FDATA[1]=[1,4095,0]");
    ASK_EQ("FDATA?", "FDATA=[[],[1,4095,0]]");
}
END_TEST

START_TEST(fdata_of_a_full_tactile_finger_fits)
{
    wsg_finger_t *f = &h_devp()->fingers.slot[0];
    f->type = FINGER_DSA;
    f->data_count = WSG_FINGER_DATA_MAX;
    for (unsigned i = 0; i < WSG_FINGER_DATA_MAX; i++) {
        f->data[i] = 4095.0f;
    }
    const char *reply = ask(&h_main, "FDATA[0]?");
    ck_assert(strncmp(reply, "FDATA[0]=[4095,4095,", 20) == 0);
    ck_assert_uint_eq(strlen(reply), 10 + WSG_FINGER_DATA_MAX * 5);
}
END_TEST

START_TEST(fdata_of_two_full_tactile_fingers_fits)
{
    for (unsigned s = 0; s < WSG_FINGER_COUNT; s++) {
        wsg_finger_t *f = &h_devp()->fingers.slot[s];
        f->type = FINGER_DSA;
        f->data_count = WSG_FINGER_DATA_MAX;
        for (unsigned i = 0; i < WSG_FINGER_DATA_MAX; i++) {
            f->data[i] = 4095.0f;
        }
    }
    const char *reply = ask(&h_main, "FDATA?");
    ck_assert(strncmp(reply, "FDATA=[[4095,", 13) == 0);
    ck_assert_uint_eq(strlen(reply), 9 + 2 * (1 + WSG_FINGER_DATA_MAX * 5));
    EXPECT_NONE();
}
END_TEST

/* --- motion commands: the immediate acknowledge of each form --- */

START_TEST(home_forms_ack)
{
    ASK_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
    ASK_EQ("HOME(0)", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
    ASK_EQ("HOME(1)", "ACK HOME");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
}
END_TEST

START_TEST(move_forms_ack)
{
    ASK_EQ("MOVE(50)", "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    ASK_EQ("MOVE(60, 50.5)", "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    ASK_EQ("POS?", "POS=60.0");
}
END_TEST

START_TEST(stop_faststop_fsack_ack)
{
    ASK_EQ("STOP()", "ACK STOP");
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    ASK_EQ("FSACK()", "ACK FSACK");
    ASK_EQ("FSACK()", "ACK FSACK"); /* also when nothing is latched */
}
END_TEST

/* --- verbose error messages --- */

static void verbose_on(void)
{
    ASK_EQ("VERBOSE=1", "VERBOSE=1");
}

START_TEST(verbose_error_descriptions)
{
    verbose_on();
    ASK_EQ("FOO()", "ERR FOO 14 Unknown command");
    ASK_EQ("HOME?", "ERR HOME 15 Command format error");
    ASK_EQ("MOVE()", "ERR MOVE 13 Not enough parameters to execute the command");
    ASK_EQ("BYE(1)", "ERR BYE 12 A Parameter was given, but none expected");
    ASK_EQ("PWT=111", "ERR PWT 28 Range error");
    ASK_EQ("PWT=x", "ERR PWT 24 Wrong parameter");
    ASK_EQ("SYSFLAGS[32]?", "ERR SYSFLAGS 25 Index out of bounds");
    ASK_EQ("MOVE(50)", "ERR MOVE 3 Device was not initialized");
    ASK_EQ("FDATA?", "ERR FDATA 1 Function or data is not available");
    ASK_EQ("\x01", "ERR ? 15 Command format error");
}
END_TEST

START_TEST(verbose_off_again)
{
    verbose_on();
    ASK_EQ("VERBOSE=0", "VERBOSE=0");
    ASK_EQ("FOO()", "ERR FOO 14");
}
END_TEST

START_TEST(verbose_state_errors)
{
    verbose_on();
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    ASK_EQ("HOME()", "ERR HOME 16 Access denied");
    ASK_EQ("FSACK()", "ACK FSACK");
    ASK_EQ("HOME()", "ACK HOME");
    ASK_EQ("HOME()", "ERR HOME 4 The data acquisition is already running");
    SEND("STOP()");
    EXPECT("ERR HOME 19 Command execution was aborted by the user");
    EXPECT("ACK STOP");
}
END_TEST

START_TEST(status_descriptions)
{
    ck_assert_str_eq(wsg_status_description(E_SUCCESS),
                     "No error occurred, operation was successful");
    ck_assert_str_eq(wsg_status_description(E_CMD_FAILED), "Error while executing a command");
    ck_assert_str_eq(wsg_status_description(E_AXIS_BLOCKED), "Axis blocked");
    ck_assert_str_eq(wsg_status_description(E_FILE_EXISTS), "File already exists");
    ck_assert_str_eq(wsg_status_description(WSG_STATUS_COUNT), "Unknown error");
    for (int i = 0; i < WSG_STATUS_COUNT; i++) {
        ck_assert_ptr_nonnull(wsg_status_description((wsg_status_t)i));
        ck_assert_str_ne(wsg_status_description((wsg_status_t)i), "Unknown error");
    }
}
END_TEST

Suite *commands_suite(void)
{
    Suite *s = suite_create("commands");
    TCase *query = tcase_create("queries");
    tcase_add_checked_fixture(query, h_setup, h_teardown);
    tcase_add_test(query, verbose_set_and_reply);
    tcase_add_test(query, verbose_query_is_tolerated);
    tcase_add_test(query, identity);
    tcase_add_test(query, repeated_query_lines_are_each_answered_for_their_own_bytes);
    tcase_add_test(query, repeated_query_lines_answer_as_their_parse);
    tcase_add_test(query, repeated_query_lines_report_as_their_parse);
    tcase_add_test(query, repeated_query_meets_an_injected_failure);
    tcase_add_test(query, pipelined_queries_see_the_world_change_between_inputs);
    tcase_add_test(query, float_replies_kept_or_formatted_are_the_rule_s_text);
    tcase_add_test(query, lower_case_commands_answer_upper_case);
    tcase_add_test(query, temperature);
    tcase_add_test(query, sysflags_at_power_on);
    tcase_add_test(query, state_at_power_on);
    tcase_add_test(query, gripstats_forms);
    tcase_add_test(query, pwt_and_clt_defaults);
    tcase_add_test(query, pwt_and_clt_set);
    tcase_add_test(query, stop_faststop_fsack_ack);
    tcase_add_test(query, home_forms_ack);
    suite_add_tcase(s, query);

    TCase *fingers = tcase_create("fingers");
    tcase_add_checked_fixture(fingers, h_setup, h_teardown);
    tcase_add_test(fingers, fingers_without_fingers);
    tcase_add_test(fingers, fingers_with_force_finger);
    tcase_add_test(fingers, tare_forms);
    tcase_add_test(fingers, fdata_of_tactile_finger);
    tcase_add_test(fingers, fdata_of_a_full_tactile_finger_fits);
    tcase_add_test(fingers, fdata_of_two_full_tactile_fingers_fits);
    suite_add_tcase(s, fingers);

    TCase *homed = tcase_create("homed");
    tcase_add_checked_fixture(homed, h_setup_homed, h_teardown);
    tcase_add_test(homed, move_forms_ack);
    tcase_add_test(homed, pipelined_queries_see_a_command_at_the_same_instant);
    suite_add_tcase(s, homed);

    TCase *verbose = tcase_create("verbose");
    tcase_add_checked_fixture(verbose, h_setup, h_teardown);
    tcase_add_test(verbose, verbose_error_descriptions);
    tcase_add_test(verbose, verbose_off_again);
    tcase_add_test(verbose, verbose_state_errors);
    tcase_add_test(verbose, status_descriptions);
    suite_add_tcase(s, verbose);
    return s;
}
