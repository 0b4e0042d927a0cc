/* SPDX-License-Identifier: BSD-3-Clause */
/* Every error path: ERR <NAME> <code>, terse mode, in the order
 * bad line > unknown name > syntax > shape > handler. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include "fake_device.h"
#include "unit_suites.h"

typedef struct {
    const char *line;
    const char *reply;
} exchange_t;

static void ask_all(const exchange_t *cases, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        const char *reply = ask(&h_main, cases[i].line);
        ck_assert_msg(strcmp(reply, cases[i].reply) == 0, "%s -> \"%s\", expected \"%s\"",
                      cases[i].line, reply, cases[i].reply);
        EXPECT_NONE();
    }
}

#define ASK_ALL(cases) ask_all((cases), sizeof(cases) / sizeof((cases)[0]))

START_TEST(unknown_command)
{
    static const exchange_t cases[] = {
        {"FOO()", "ERR FOO 14"},     {"FOO?", "ERR FOO 14"},
        {"FOO[1]?", "ERR FOO 14"},   {"FOO=1", "ERR FOO 14"},
        {"foo", "ERR FOO 14"},       {"FOO(1,", "ERR FOO 14"},
        {"HO ME()", "ERR HO 14"},    {"HOMEX()", "ERR HOMEX 14"},
        {"HOME_()", "ERR HOME_ 14"}, {"ABCDEFGHIJKLMNOPQRSTUVWXYZ()", "ERR ABCDEFGHIJKLMNO 14"},
    };
    ASK_ALL(cases);
}
END_TEST

START_TEST(format_error)
{
    static const exchange_t cases[] = {
        {"HOME", "ERR HOME 15"},
        {"HOME?", "ERR HOME 15"},
        {"HOME[0]?", "ERR HOME 15"},
        {"HOME=1", "ERR HOME 15"},
        {"POS()", "ERR POS 15"},
        {"POS=1", "ERR POS 15"},
        {"POS[0]?", "ERR POS 15"},
        {"PWT[0]?", "ERR PWT 15"},
        {"PWT()", "ERR PWT 15"},
        {"SYSFLAGS=1", "ERR SYSFLAGS 15"},
        {"VERBOSE(1)", "ERR VERBOSE 15"},
        {"BYE?", "ERR BYE 15"},
        {"AUTOSEND?", "ERR AUTOSEND 15"},
        {"GRIPSTATS()", "ERR GRIPSTATS 15"},
        {"HOME() x", "ERR HOME 15"},
        {"MOVE(50", "ERR MOVE 15"},
        {"MOVE(50,)", "ERR MOVE 15"},
        {"MOVE(,)", "ERR MOVE 15"},
        {"PWT=", "ERR PWT 15"},
        {"SYSFLAGS[]?", "ERR SYSFLAGS 15"},
        {"SYSFLAGS[1.0]?", "ERR SYSFLAGS 15"},
        {"SYSFLAGS[1]", "ERR SYSFLAGS 15"},
        {"123", "ERR ? 15"},
        {"(1)", "ERR ? 15"},
        {"\"POS\"?", "ERR ? 15"},
    };
    ASK_ALL(cases);
}
END_TEST

START_TEST(not_enough_params)
{
    static const exchange_t cases[] = {
        {"MOVE()", "ERR MOVE 13"},
        {"AUTOSEND()", "ERR AUTOSEND 13"},
        {"AUTOSEND(\"POS\")", "ERR AUTOSEND 13"},
        {"move()", "ERR MOVE 13"},
    };
    ASK_ALL(cases);
}
END_TEST

START_TEST(too_many_params)
{
    static const exchange_t cases[] = {
        {"BYE(1)", "ERR BYE 12"},
        {"HOME(1,0)", "ERR HOME 12"},
        {"MOVE(1,2,3)", "ERR MOVE 12"},
        {"GRIP(1,2,3,4)", "ERR GRIP 12"},
        {"GRIP(1,2,3,4,5,6,7)", "ERR GRIP 12"},
        {"RELEASE(1,2,3)", "ERR RELEASE 12"},
        {"AUTOSEND(\"POS\",10,1,2)", "ERR AUTOSEND 12"},
        {"STOP(1)", "ERR STOP 12"},
        {"FASTSTOP(1)", "ERR FASTSTOP 12"},
        {"FSACK(1)", "ERR FSACK 12"},
        {"TARE(0,1)", "ERR TARE 12"},
    };
    ASK_ALL(cases);
}
END_TEST

START_TEST(wrong_type)
{
    static const exchange_t cases[] = {
        {"MOVE(\"50\")", "ERR MOVE 24"},
        {"MOVE(abc)", "ERR MOVE 24"},
        {"MOVE(12abc)", "ERR MOVE 24"},
        {"MOVE(50,fast)", "ERR MOVE 24"},
        {"GRIP(x)", "ERR GRIP 24"},
        {"RELEASE(\"1\")", "ERR RELEASE 24"},
        {"PWT=\"a\"", "ERR PWT 24"},
        {"CLT=abc", "ERR CLT 24"},
        {"VERBOSE=0.5", "ERR VERBOSE 24"},
        {"VERBOSE=\"1\"", "ERR VERBOSE 24"},
        {"HOME(0.5)", "ERR HOME 24"},
        {"HOME(maybe)", "ERR HOME 24"},
        {"TARE(0.5)", "ERR TARE 24"},
        {"TARE(\"0\")", "ERR TARE 24"},
        {"AUTOSEND(10,10)", "ERR AUTOSEND 24"},
        {"AUTOSEND(\"FOO\",10)", "ERR AUTOSEND 24"},
        {"AUTOSEND(\"POS\",10.5)", "ERR AUTOSEND 24"},
        {"AUTOSEND(\"POS\",\"10\")", "ERR AUTOSEND 24"},
        {"AUTOSEND(\"POS\",10,x)", "ERR AUTOSEND 24"},
        {"AUTOSEND(\"GRIPSTATE\",10,0.5)", "ERR AUTOSEND 24"},
    };
    ASK_ALL(cases);
}
END_TEST

START_TEST(index_out_of_bounds)
{
    static const exchange_t cases[] = {
        {"SYSFLAGS[32]?", "ERR SYSFLAGS 25"},  {"SYSFLAGS[-1]?", "ERR SYSFLAGS 25"},
        {"GRIPSTATS[3]?", "ERR GRIPSTATS 25"}, {"GRIPSTATS[-1]?", "ERR GRIPSTATS 25"},
        {"FDATA[2]?", "ERR FDATA 25"},         {"FTYPE[2]?", "ERR FTYPE 25"},
        {"FFLAGS[-1]?", "ERR FFLAGS 25"},      {"TARE(2)", "ERR TARE 25"},
        {"TARE(-1)", "ERR TARE 25"},
    };
    ASK_ALL(cases);
}
END_TEST

START_TEST(range_errors)
{
    static const exchange_t cases[] = {
        {"VERBOSE=2", "ERR VERBOSE 28"},
        {"VERBOSE=-1", "ERR VERBOSE 28"},
        {"HOME(2)", "ERR HOME 28"},
        {"PWT=-1", "ERR PWT 28"},
        {"PWT=110.5", "ERR PWT 28"},
        {"CLT=-0.5", "ERR CLT 28"},
        {"AUTOSEND(\"POS\",9)", "ERR AUTOSEND 28"},
        {"AUTOSEND(\"POS\",1)", "ERR AUTOSEND 28"},
        {"AUTOSEND(\"POS\",-10)", "ERR AUTOSEND 28"},
        {"AUTOSEND(\"POS\",3600001)", "ERR AUTOSEND 28"},
        {"AUTOSEND(\"POS\",10,-1)", "ERR AUTOSEND 28"},
        {"AUTOSEND(\"SYSFLAGS\",10,2)", "ERR AUTOSEND 28"},
    };
    ASK_ALL(cases);
}
END_TEST

START_TEST(motion_range_errors)
{
    static const exchange_t cases[] = {
        {"MOVE(110.5)", "ERR MOVE 28"},    {"MOVE(-0.1)", "ERR MOVE 28"},
        {"MOVE(50,4.9)", "ERR MOVE 28"},   {"MOVE(50,421)", "ERR MOVE 28"},
        {"MOVE(50,0)", "ERR MOVE 28"},     {"MOVE(1e300)", "ERR MOVE 28"},
        {"MOVE(-1e300)", "ERR MOVE 28"},   {"GRIP(4.9)", "ERR GRIP 28"},
        {"GRIP(81)", "ERR GRIP 28"},       {"GRIP(40,111)", "ERR GRIP 28"},
        {"GRIP(40,-1)", "ERR GRIP 28"},    {"GRIP(40,30,500)", "ERR GRIP 28"},
        {"GRIP(40,30,1)", "ERR GRIP 28"},  {"RELEASE(111)", "ERR RELEASE 28"},
        {"RELEASE(-1)", "ERR RELEASE 28"}, {"RELEASE(10,1)", "ERR RELEASE 28"},
    };
    ASK_ALL(cases);
    ASK_EQ("GRIPSTATS?", "GRIPSTATS=[0,0,0]"); /* refused grips are not counted */
}
END_TEST

START_TEST(motion_before_home)
{
    static const exchange_t cases[] = {
        {"MOVE(50)", "ERR MOVE 3"},
        {"GRIP()", "ERR GRIP 3"},
        {"GRIP(40,30)", "ERR GRIP 3"},
        {"RELEASE()", "ERR RELEASE 3"},
    };
    ASK_ALL(cases);
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
}
END_TEST

START_TEST(motion_while_homing)
{
    ASK_EQ("HOME()", "ACK HOME");
    ASK_EQ("HOME()", "ERR HOME 4");
    advance_ms(10);
    ASK_EQ("HOME(0)", "ERR HOME 4");
    ASK_EQ("MOVE(50)", "ERR MOVE 4");
    ASK_EQ("GRIP()", "ERR GRIP 4");
    ck_assert_int_ge(run_until_line(&h_main, "FIN HOME", 3000), 0);
    EXPECT_NONE();
}
END_TEST

START_TEST(motion_while_moving)
{
    ASK_EQ("MOVE(10)", "ACK MOVE");
    advance_ms(5);
    ASK_EQ("GRIP()", "ERR GRIP 4");
    ASK_EQ("HOME()", "ERR HOME 4");
    ASK_EQ("RELEASE()", "ERR RELEASE 4");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    EXPECT_NONE();
    ASK_EQ("POS?", "POS=10.0");
}
END_TEST

START_TEST(motion_in_fast_stop)
{
    ASK_EQ("FASTSTOP()", "ACK FASTSTOP");
    static const exchange_t cases[] = {
        {"HOME()", "ERR HOME 16"},
        {"MOVE(50)", "ERR MOVE 16"},
        {"GRIP()", "ERR GRIP 16"},
        {"RELEASE()", "ERR RELEASE 16"},
    };
    ASK_ALL(cases);
    ASK_EQ("STOP()", "ACK STOP"); /* not motion: allowed */
    ASK_EQ("FSACK()", "ACK FSACK");
    ASK_EQ("MOVE(50)", "ACK MOVE");
}
END_TEST

START_TEST(release_without_grip)
{
    ASK_EQ("RELEASE()", "ERR RELEASE 16");
    ASK_EQ("RELEASE(5)", "ERR RELEASE 16");
    ASK_EQ("GRIPSTATE?", "GRIPSTATE=0");
}
END_TEST

START_TEST(release_while_positioning)
{
    ASK_EQ("MOVE(20)", "ACK MOVE");
    ck_assert_int_ge(run_until_line(&h_main, "FIN MOVE", 3000), 0);
    ASK_EQ("RELEASE()", "ERR RELEASE 16");
}
END_TEST

START_TEST(error_precedence)
{
    /* a bad byte beats an unknown name, which beats a syntax error */
    const uint8_t bad[] = {'F', 'O', 'O', 0x01, '(', ')', '\n'};
    h_send_bytes(&h_main, bad, sizeof(bad));
    EXPECT("ERR FOO 15");
    ASK_EQ("FOO(\"x", "ERR FOO 14");
    /* syntax is checked before the handler's argument checks */
    ASK_EQ("MOVE(500,)", "ERR MOVE 15");
    /* the argument count before its type */
    ASK_EQ("MOVE(a,b,c)", "ERR MOVE 12");
}
END_TEST

Suite *errors_suite(void)
{
    Suite *s = suite_create("errors");
    TCase *syntax = tcase_create("syntax");
    tcase_add_checked_fixture(syntax, h_setup, h_teardown);
    tcase_add_test(syntax, unknown_command);
    tcase_add_test(syntax, format_error);
    tcase_add_test(syntax, not_enough_params);
    tcase_add_test(syntax, too_many_params);
    tcase_add_test(syntax, wrong_type);
    tcase_add_test(syntax, index_out_of_bounds);
    tcase_add_test(syntax, range_errors);
    tcase_add_test(syntax, error_precedence);
    tcase_add_test(syntax, motion_before_home);
    tcase_add_test(syntax, motion_while_homing);
    suite_add_tcase(s, syntax);

    TCase *state = tcase_create("state");
    tcase_add_checked_fixture(state, h_setup_homed, h_teardown);
    tcase_add_test(state, motion_range_errors);
    tcase_add_test(state, motion_while_moving);
    tcase_add_test(state, motion_in_fast_stop);
    tcase_add_test(state, release_without_grip);
    tcase_add_test(state, release_while_positioning);
    suite_add_tcase(s, state);
    return s;
}
