/* SPDX-License-Identifier: BSD-3-Clause */
/* wsg_gcl_parse_line(): the GCL syntax on its own, without a device. */
#include <check.h>
#include <string.h>

#include "wsg/gcl_parse.h"
#include "unit_suites.h"

static gcl_command_t cmd;

static wsg_status_t parse(const char *line)
{
    return wsg_gcl_parse_line(line, strlen(line), &cmd);
}

static void assert_number(unsigned i, double value, bool integer_syntax)
{
    ck_assert_int_eq(cmd.args[i].kind, GCL_ARG_NUMBER);
    ck_assert_double_eq_tol(cmd.args[i].number, value, 1e-9);
    ck_assert_int_eq(cmd.args[i].integer_syntax, integer_syntax);
}

/* --- forms --- */

START_TEST(call_without_args)
{
    ck_assert_int_eq(parse("HOME()"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "HOME");
    ck_assert_int_eq(cmd.form, GCL_FORM_CALL);
    ck_assert_uint_eq(cmd.argc, 0);
}
END_TEST

START_TEST(call_with_args)
{
    ck_assert_int_eq(parse("GRIP(40,30.5,100)"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "GRIP");
    ck_assert_uint_eq(cmd.argc, 3);
    assert_number(0, 40.0, true);
    assert_number(1, 30.5, false);
    assert_number(2, 100.0, true);
}
END_TEST

START_TEST(query)
{
    ck_assert_int_eq(parse("POS?"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "POS");
    ck_assert_int_eq(cmd.form, GCL_FORM_QUERY);
    ck_assert_uint_eq(cmd.argc, 0);
}
END_TEST

START_TEST(indexed_query)
{
    ck_assert_int_eq(parse("SYSFLAGS[12]?"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "SYSFLAGS");
    ck_assert_int_eq(cmd.form, GCL_FORM_INDEXED_QUERY);
    ck_assert_int_eq(cmd.index, 12);
}
END_TEST

START_TEST(negative_index_is_syntax)
{
    /* out of bounds is the handler's business, not the parser's */
    ck_assert_int_eq(parse("SYSFLAGS[-1]?"), E_SUCCESS);
    ck_assert_int_eq(cmd.index, -1);
}
END_TEST

START_TEST(set)
{
    ck_assert_int_eq(parse("PWT=2.5"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "PWT");
    ck_assert_int_eq(cmd.form, GCL_FORM_SET);
    ck_assert_uint_eq(cmd.argc, 1);
    assert_number(0, 2.5, false);
}
END_TEST

/* --- white space and case --- */

START_TEST(spaces_and_tabs_everywhere)
{
    ck_assert_int_eq(parse(" \tMOVE \t( 50 ,\t20 ) \t"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "MOVE");
    ck_assert_uint_eq(cmd.argc, 2);
    assert_number(0, 50.0, true);
    assert_number(1, 20.0, true);
    ck_assert_int_eq(parse("SYSFLAGS [ 3 ] ?"), E_SUCCESS);
    ck_assert_int_eq(cmd.index, 3);
    ck_assert_int_eq(parse("PWT = 4"), E_SUCCESS);
    assert_number(0, 4.0, true);
}
END_TEST

START_TEST(space_inside_name_splits_it)
{
    ck_assert_int_eq(parse("HO ME()"), E_CMD_FORMAT_ERROR);
    ck_assert_str_eq(cmd.name, "HO");
}
END_TEST

START_TEST(name_is_upper_cased)
{
    ck_assert_int_eq(parse("mOve(50)"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "MOVE");
    ck_assert_int_eq(parse("move(50)"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "MOVE");
}
END_TEST

START_TEST(name_with_digits_and_underscore)
{
    ck_assert_int_eq(parse("_A1b2?"), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "_A1B2");
}
END_TEST

START_TEST(too_long_name_is_truncated)
{
    ck_assert_int_eq(parse("ABCDEFGHIJKLMNOPQRSTUVWXYZ()"), E_SUCCESS);
    ck_assert_uint_eq(strlen(cmd.name), GCL_NAME_MAX);
    ck_assert_str_eq(cmd.name, "ABCDEFGHIJKLMNO");
}
END_TEST

/* --- numbers --- */

START_TEST(number_forms)
{
    static const struct {
        const char *line;
        double value;
        bool integer_syntax;
    } cases[] = {
        {"M(50)", 50.0, true},    {"M(50.00)", 50.0, false},    {"M(20.000000)", 20.0, false},
        {"M(-3)", -3.0, true},    {"M(+7)", 7.0, true},         {"M(1e2)", 100.0, false},
        {"M(1E2)", 100.0, false}, {"M(2.5e-1)", 0.25, false},   {"M(.5)", 0.5, false},
        {"M(5.)", 5.0, false},    {"M(-0.125)", -0.125, false}, {"M(1e+3)", 1000.0, false},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        ck_assert_msg(parse(cases[i].line) == E_SUCCESS, "%s", cases[i].line);
        ck_assert_uint_eq(cmd.argc, 1);
        assert_number(0, cases[i].value, cases[i].integer_syntax);
    }
}
END_TEST

START_TEST(bad_number_tokens)
{
    static const char *const lines[] = {
        "M(12abc)", "M(1e)", "M(1e+)", "M(-)", "M(.)", "M(+)", "M(1x)", "M(1e400)", "M(--1)",
    };
    for (size_t i = 0; i < sizeof(lines) / sizeof(lines[0]); i++) {
        ck_assert_msg(parse(lines[i]) == E_INVALID_PARAMETER, "%s", lines[i]);
        ck_assert_str_eq(cmd.name, "M");
    }
}
END_TEST

START_TEST(number_followed_by_garbage)
{
    ck_assert_int_eq(parse("M(1.2.3)"), E_CMD_FORMAT_ERROR);
    ck_assert_int_eq(parse("M(1 2)"), E_CMD_FORMAT_ERROR);
    ck_assert_int_eq(parse("M(1-2)"), E_CMD_FORMAT_ERROR);
}
END_TEST

/* --- strings and words --- */

START_TEST(strings)
{
    ck_assert_int_eq(parse("AUTOSEND(\"POS\", 10)"), E_SUCCESS);
    ck_assert_int_eq(cmd.args[0].kind, GCL_ARG_STRING);
    ck_assert_str_eq(cmd.args[0].text, "POS");
    assert_number(1, 10.0, true);
    ck_assert_int_eq(parse("X(\"a, (b)\")"), E_SUCCESS);
    ck_assert_str_eq(cmd.args[0].text, "a, (b)");
    ck_assert_int_eq(parse("X(\"\")"), E_SUCCESS);
    ck_assert_int_eq(cmd.args[0].kind, GCL_ARG_STRING);
    ck_assert_str_eq(cmd.args[0].text, "");
}
END_TEST

START_TEST(string_keeps_case)
{
    ck_assert_int_eq(parse("X(\"pOs\")"), E_SUCCESS);
    ck_assert_str_eq(cmd.args[0].text, "pOs");
}
END_TEST

START_TEST(bad_strings)
{
    ck_assert_int_eq(parse("X(\"POS)"), E_INVALID_PARAMETER);
    ck_assert_int_eq(parse("X(\"POS"), E_INVALID_PARAMETER);
    char line[64] = "X(\"";
    memset(line + 3, 'a', GCL_STRING_MAX + 1);
    strcpy(line + 3 + GCL_STRING_MAX + 1, "\")");
    ck_assert_int_eq(parse(line), E_INVALID_PARAMETER);
}
END_TEST

START_TEST(longest_string)
{
    char line[64] = "X(\"";
    memset(line + 3, 'a', GCL_STRING_MAX);
    strcpy(line + 3 + GCL_STRING_MAX, "\")");
    ck_assert_int_eq(parse(line), E_SUCCESS);
    ck_assert_uint_eq(strlen(cmd.args[0].text), GCL_STRING_MAX);
}
END_TEST

START_TEST(words)
{
    ck_assert_int_eq(parse("AUTOSEND(pos, 10, true)"), E_SUCCESS);
    ck_assert_int_eq(cmd.args[0].kind, GCL_ARG_WORD);
    ck_assert_str_eq(cmd.args[0].text, "pos");
    ck_assert_int_eq(cmd.args[2].kind, GCL_ARG_WORD);
    ck_assert_str_eq(cmd.args[2].text, "true");
}
END_TEST

START_TEST(too_long_word)
{
    char line[64] = "X(";
    memset(line + 2, 'w', GCL_STRING_MAX + 1);
    strcpy(line + 2 + GCL_STRING_MAX + 1, ")");
    ck_assert_int_eq(parse(line), E_INVALID_PARAMETER);
}
END_TEST

START_TEST(text_equals_ignores_case)
{
    ck_assert(wsg_gcl_text_equals("pOs", "POS"));
    ck_assert(wsg_gcl_text_equals("", ""));
    ck_assert(!wsg_gcl_text_equals("POSX", "POS"));
    ck_assert(!wsg_gcl_text_equals("PO", "POS"));
}
END_TEST

/* Lines only HTTP sends, and commands that must not look like them. */
START_TEST(http_lines_are_told_from_commands)
{
    ck_assert(wsg_gcl_line_is_http("POST / HTTP/1.1"));
    ck_assert(wsg_gcl_line_is_http("GET /x?MOVE(0) HTTP/1.0"));
    ck_assert(wsg_gcl_line_is_http("OPTIONS * HTTP/1.1"));
    ck_assert(wsg_gcl_line_is_http("CONNECT http://host:1000/ HTTP/1.1"));
    ck_assert(wsg_gcl_line_is_http("Host: 127.0.0.1:1000"));
    ck_assert(wsg_gcl_line_is_http("content-type:text/plain"));
    ck_assert(!wsg_gcl_line_is_http("MOVE(50)"));
    ck_assert(!wsg_gcl_line_is_http("POS?"));
    ck_assert(!wsg_gcl_line_is_http("AUTOSEND(\"POS\",10)"));
    ck_assert(!wsg_gcl_line_is_http("PWT=5"));
    ck_assert(!wsg_gcl_line_is_http("SYSFLAGS[12]?"));
    ck_assert(!wsg_gcl_line_is_http("post / HTTP/1.1")); /* methods are capitals */
    ck_assert(!wsg_gcl_line_is_http("POST"));
    ck_assert(!wsg_gcl_line_is_http(""));
}
END_TEST

/* --- argument lists --- */

START_TEST(empty_arguments)
{
    static const char *const lines[] = {"M(,)", "M(1,)", "M(,1)", "M(1,,2)", "M( , )"};
    for (size_t i = 0; i < sizeof(lines) / sizeof(lines[0]); i++) {
        ck_assert_msg(parse(lines[i]) == E_CMD_FORMAT_ERROR, "%s", lines[i]);
    }
}
END_TEST

START_TEST(unclosed_call)
{
    ck_assert_int_eq(parse("M("), E_CMD_FORMAT_ERROR);
    ck_assert_int_eq(parse("M(1"), E_CMD_FORMAT_ERROR);
    ck_assert_int_eq(parse("M(1,2"), E_CMD_FORMAT_ERROR);
    ck_assert_str_eq(cmd.name, "M");
}
END_TEST

START_TEST(extra_args_are_counted)
{
    ck_assert_int_eq(parse("M(1,2,3,4,5,6)"), E_SUCCESS);
    ck_assert_uint_eq(cmd.argc, 6);
    assert_number(GCL_ARGS_MAX - 1, 4.0, true);
}
END_TEST

/* --- malformed lines --- */

START_TEST(trailing_garbage)
{
    static const char *const lines[] = {"HOME() x", "HOME()()",      "POS??",  "POS?1",
                                        "PWT=1 2",  "SYSFLAGS[1]?x", "HOME();"};
    for (size_t i = 0; i < sizeof(lines) / sizeof(lines[0]); i++) {
        ck_assert_msg(parse(lines[i]) == E_CMD_FORMAT_ERROR, "%s", lines[i]);
        ck_assert_msg(cmd.name[0] != '\0', "%s", lines[i]);
    }
}
END_TEST

START_TEST(no_form)
{
    ck_assert_int_eq(parse("HOME"), E_CMD_FORMAT_ERROR);
    ck_assert_str_eq(cmd.name, "HOME");
    ck_assert_int_eq(parse("HOME!"), E_CMD_FORMAT_ERROR);
    ck_assert_int_eq(parse("PWT="), E_CMD_FORMAT_ERROR);
    ck_assert_int_eq(parse("PWT=  "), E_CMD_FORMAT_ERROR);
}
END_TEST

START_TEST(no_name)
{
    static const char *const lines[] = {"", "()", "?", "123()", "\"POS\"?", "=1", "[1]?"};
    for (size_t i = 0; i < sizeof(lines) / sizeof(lines[0]); i++) {
        ck_assert_msg(parse(lines[i]) == E_CMD_FORMAT_ERROR, "%s", lines[i]);
        ck_assert_str_eq(cmd.name, "");
    }
}
END_TEST

START_TEST(bad_index)
{
    static const char *const lines[] = {"S[]?", "S[1.0]?", "S[1e1]?", "S[x]?",
                                        "S[1]", "S[1?",    "S[1]]?",  "S[99999999999]?"};
    for (size_t i = 0; i < sizeof(lines) / sizeof(lines[0]); i++) {
        ck_assert_msg(parse(lines[i]) == E_CMD_FORMAT_ERROR, "%s", lines[i]);
    }
}
END_TEST

START_TEST(length_is_respected)
{
    /* the parser reads exactly len bytes; what follows is not its business */
    const char *line = "POS?garbage";
    ck_assert_int_eq(wsg_gcl_parse_line(line, 4, &cmd), E_SUCCESS);
    ck_assert_str_eq(cmd.name, "POS");
}
END_TEST

Suite *parse_suite(void)
{
    Suite *s = suite_create("parse");
    TCase *forms = tcase_create("forms");
    tcase_add_test(forms, call_without_args);
    tcase_add_test(forms, call_with_args);
    tcase_add_test(forms, query);
    tcase_add_test(forms, indexed_query);
    tcase_add_test(forms, negative_index_is_syntax);
    tcase_add_test(forms, set);
    tcase_add_test(forms, spaces_and_tabs_everywhere);
    tcase_add_test(forms, space_inside_name_splits_it);
    tcase_add_test(forms, name_is_upper_cased);
    tcase_add_test(forms, name_with_digits_and_underscore);
    tcase_add_test(forms, too_long_name_is_truncated);
    tcase_add_test(forms, length_is_respected);
    suite_add_tcase(s, forms);

    TCase *tokens = tcase_create("tokens");
    tcase_add_test(tokens, number_forms);
    tcase_add_test(tokens, bad_number_tokens);
    tcase_add_test(tokens, number_followed_by_garbage);
    tcase_add_test(tokens, strings);
    tcase_add_test(tokens, string_keeps_case);
    tcase_add_test(tokens, bad_strings);
    tcase_add_test(tokens, longest_string);
    tcase_add_test(tokens, words);
    tcase_add_test(tokens, too_long_word);
    tcase_add_test(tokens, text_equals_ignores_case);
    tcase_add_test(tokens, http_lines_are_told_from_commands);
    suite_add_tcase(s, tokens);

    TCase *errors = tcase_create("errors");
    tcase_add_test(errors, empty_arguments);
    tcase_add_test(errors, unclosed_call);
    tcase_add_test(errors, extra_args_are_counted);
    tcase_add_test(errors, trailing_garbage);
    tcase_add_test(errors, no_form);
    tcase_add_test(errors, no_name);
    tcase_add_test(errors, bad_index);
    suite_add_tcase(s, errors);
    return s;
}
