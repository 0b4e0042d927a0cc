/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the JSON writer (host/os/json_writer.c): separators,
 * nesting, escaping, and numbers as the device writes them. cJSON parses
 * every text back, so what the writer produces is JSON. */
#include <check.h>
#include <cjson/cJSON.h>
#include <stdlib.h>
#include <string.h>

#include "host_suites.h"
#include "json_writer.h"

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
    tcase_add_test(tc, a_long_text_grows_the_buffer);
    tcase_add_test(tc, a_raw_prefix_stands_before_the_json);
    suite_add_tcase(s, tc);
    return s;
}
