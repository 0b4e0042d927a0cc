/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the JSON writer (host/os/json_writer.c): separators,
 * nesting, escaping, and numbers as the device writes them. cJSON parses
 * every text back, so what the writer produces is JSON. */
#include <check.h>
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "host_suites.h"
#include "json_writer.h"
#include "wsg/wsg_textbuf.h"

/* The writer's text, checked to parse as JSON. */
static char *finish(json_writer_t *j)
{
    size_t len = 0;
    char *text = json_writer_take(j, &len);
    ck_assert_ptr_nonnull(text);
    ck_assert_uint_eq(len, strlen(text));
    cJSON *parsed = cJSON_Parse(text);
    ck_assert_msg(parsed != NULL, "not JSON: %s", text);
    cJSON_Delete(parsed);
    return text;
}

START_TEST(objects_and_arrays_have_commas_between_values_only)
{
    json_writer_t j;
    json_writer_init(&j);
    json_writer_open_object(&j, NULL);
    json_writer_uint(&j, "a", 1);
    json_writer_open_array(&j, "list");
    json_writer_open_object(&j, NULL);
    json_writer_close_object(&j);
    json_writer_bool(&j, NULL, true);
    json_writer_null(&j, NULL);
    json_writer_close_array(&j);
    json_writer_open_array(&j, "empty");
    json_writer_close_array(&j);
    json_writer_string(&j, "none", NULL);
    json_writer_close_object(&j);
    char *text = finish(&j);
    ck_assert_str_eq(text, "{\"a\":1,\"list\":[{},true,null],\"empty\":[],\"none\":null}");
    free(text);
}
END_TEST

START_TEST(strings_escape_quotes_backslashes_and_control_characters)
{
    json_writer_t j;
    json_writer_init(&j);
    json_writer_open_array(&j, NULL);
    json_writer_string(&j, NULL,
                       "a\"b\\c\nd\x01\x1f"
                       "\xc3\xa9");
    json_writer_close_array(&j);
    char *text = finish(&j);
    ck_assert_str_eq(text, "[\"a\\\"b\\\\c\\u000ad\\u0001\\u001f\xc3\xa9\"]");
    cJSON *parsed = cJSON_Parse(text);
    ck_assert_str_eq(cJSON_GetArrayItem(parsed, 0)->valuestring, "a\"b\\c\nd\x01\x1f\xc3\xa9");
    cJSON_Delete(parsed);
    free(text);
}
END_TEST

START_TEST(numbers_are_written_as_the_device_writes_them)
{
    json_writer_t j;
    json_writer_init(&j);
    json_writer_open_array(&j, NULL);
    json_writer_float(&j, NULL, 110.0f);
    json_writer_float(&j, NULL, -3.125f);
    json_writer_float(&j, NULL, 0.599f);
    json_writer_uint(&j, NULL, 0);
    json_writer_uint(&j, NULL, 18446744073709551615ull);
    json_writer_ms(&j, NULL, 0);
    json_writer_ms(&j, NULL, 1500);
    json_writer_ms(&j, NULL, 1234567);
    json_writer_ms(&j, NULL, 7001);
    json_writer_close_array(&j);
    char *text = finish(&j);
    ck_assert_str_eq(text, "[110.0,-3.125,0.599,0,18446744073709551615,0,1.5,1234.567,7.001]");
    free(text);
}
END_TEST

/* Whole numbers take a path of their own: the text is the core's all the
 * same, for every sign and size, -0 included (never "-0.0"). */
START_TEST(whole_numbers_are_written_as_the_core_writes_them)
{
    static const float values[] = {0.0f,    -0.0f,         1.0f,         -1.0f,         94.0f,
                                   1156.0f, -3.0f,         999999999.0f, -999999999.0f, 1e9f,
                                   -1e9f,   2147483648.0f, 16777217.0f,  0.5f};
    for (size_t i = 0; i < sizeof(values) / sizeof(values[0]); i++) {
        char core[WSG_TEXTBUF_FLOAT_MAX + 1];
        core[wsg_textbuf_format_float(core, values[i])] = '\0';
        json_writer_t j;
        json_writer_init(&j);
        json_writer_float(&j, NULL, values[i]);
        char *text = finish(&j);
        ck_assert_str_eq(text, core);
        free(text);
    }
}
END_TEST

/* Keys and strings are copied in one piece up to a length: longer ones are
 * written whole all the same. */
START_TEST(long_keys_and_strings_are_written_whole)
{
    char key[101];
    char value[301];
    memset(key, 'k', sizeof(key) - 1);
    key[sizeof(key) - 1] = '\0';
    memset(value, 'v', sizeof(value) - 1);
    value[sizeof(value) - 1] = '\0';
    json_writer_t j;
    json_writer_init(&j);
    json_writer_open_object(&j, NULL);
    json_writer_string(&j, key, value);
    json_writer_uint(&j, key, 7);
    json_writer_close_object(&j);
    char *text = finish(&j);
    char expected[2 * sizeof(key) + sizeof(value) + 16];
    snprintf(expected, sizeof(expected), "{\"%s\":\"%s\",\"%s\":7}", key, value, key);
    ck_assert_str_eq(text, expected);
    free(text);
}
END_TEST

START_TEST(a_long_text_grows_the_buffer)
{
    json_writer_t j;
    json_writer_init(&j);
    json_writer_open_array(&j, NULL);
    for (unsigned i = 0; i < 5000; i++) {
        json_writer_uint(&j, NULL, i);
    }
    json_writer_close_array(&j);
    char *text = finish(&j);
    cJSON *parsed = cJSON_Parse(text);
    ck_assert_int_eq(cJSON_GetArraySize(parsed), 5000);
    ck_assert_int_eq(cJSON_GetArrayItem(parsed, 4999)->valueint, 4999);
    cJSON_Delete(parsed);
    free(text);
}
END_TEST

START_TEST(a_raw_prefix_stands_before_the_json)
{
    json_writer_t j;
    json_writer_init(&j);
    json_writer_raw(&j, "data: ", 6);
    json_writer_open_object(&j, NULL);
    json_writer_close_object(&j);
    size_t len = 0;
    char *text = json_writer_take(&j, &len);
    ck_assert_str_eq(text, "data: {}");
    ck_assert_uint_eq(len, 8);
    free(text);
}
END_TEST

Suite *json_writer_suite(void)
{
    Suite *s = suite_create("json_writer");
    TCase *tc = tcase_create("writer");
    tcase_add_test(tc, objects_and_arrays_have_commas_between_values_only);
    tcase_add_test(tc, strings_escape_quotes_backslashes_and_control_characters);
    tcase_add_test(tc, numbers_are_written_as_the_device_writes_them);
    tcase_add_test(tc, whole_numbers_are_written_as_the_core_writes_them);
    tcase_add_test(tc, long_keys_and_strings_are_written_whole);
    tcase_add_test(tc, a_long_text_grows_the_buffer);
    tcase_add_test(tc, a_raw_prefix_stands_before_the_json);
    suite_add_tcase(s, tc);
    return s;
}
