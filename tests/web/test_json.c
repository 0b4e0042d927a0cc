/* SPDX-License-Identifier: BSD-3-Clause */
/* Check tests of the web's JSON writer (host/web/web_json.c): separators,
 * nesting, escaping, and numbers as the device writes them. cJSON parses
 * every text back, so what the writer produces is JSON. */
#include <check.h>
#include <cjson/cJSON.h>
#include <stdlib.h>
#include <string.h>

#include "web/web_json.h"

/* The writer's text, checked to parse as JSON. */
static char *finish(web_json_t *j)
{
    size_t len = 0;
    char *text = web_json_take(j, &len);
    ck_assert_ptr_nonnull(text);
    ck_assert_uint_eq(len, strlen(text));
    cJSON *parsed = cJSON_Parse(text);
    ck_assert_msg(parsed != NULL, "not JSON: %s", text);
    cJSON_Delete(parsed);
    return text;
}

START_TEST(objects_and_arrays_have_commas_between_values_only)
{
    web_json_t j;
    web_json_init(&j);
    web_json_open_object(&j, NULL);
    web_json_uint(&j, "a", 1);
    web_json_open_array(&j, "list");
    web_json_open_object(&j, NULL);
    web_json_close_object(&j);
    web_json_bool(&j, NULL, true);
    web_json_null(&j, NULL);
    web_json_close_array(&j);
    web_json_open_array(&j, "empty");
    web_json_close_array(&j);
    web_json_string(&j, "none", NULL);
    web_json_close_object(&j);
    char *text = finish(&j);
    ck_assert_str_eq(text, "{\"a\":1,\"list\":[{},true,null],\"empty\":[],\"none\":null}");
    free(text);
}
END_TEST

START_TEST(strings_escape_quotes_backslashes_and_control_characters)
{
    web_json_t j;
    web_json_init(&j);
    web_json_open_array(&j, NULL);
    web_json_string(&j, NULL,
                    "a\"b\\c\nd\x01\x1f"
                    "\xc3\xa9");
    web_json_close_array(&j);
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
    web_json_t j;
    web_json_init(&j);
    web_json_open_array(&j, NULL);
    web_json_float(&j, NULL, 110.0f);
    web_json_float(&j, NULL, -3.125f);
    web_json_float(&j, NULL, 0.599f);
    web_json_uint(&j, NULL, 0);
    web_json_uint(&j, NULL, 18446744073709551615ull);
    web_json_ms(&j, NULL, 0);
    web_json_ms(&j, NULL, 1500);
    web_json_ms(&j, NULL, 1234567);
    web_json_ms(&j, NULL, 7001);
    web_json_close_array(&j);
    char *text = finish(&j);
    ck_assert_str_eq(text, "[110.0,-3.125,0.599,0,18446744073709551615,0,1.5,1234.567,7.001]");
    free(text);
}
END_TEST

START_TEST(a_long_text_grows_the_buffer)
{
    web_json_t j;
    web_json_init(&j);
    web_json_open_array(&j, NULL);
    for (unsigned i = 0; i < 5000; i++) {
        web_json_uint(&j, NULL, i);
    }
    web_json_close_array(&j);
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
    web_json_t j;
    web_json_init(&j);
    web_json_raw(&j, "data: ", 6);
    web_json_open_object(&j, NULL);
    web_json_close_object(&j);
    size_t len = 0;
    char *text = web_json_take(&j, &len);
    ck_assert_str_eq(text, "data: {}");
    ck_assert_uint_eq(len, 8);
    free(text);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("web_json");
    TCase *tc = tcase_create("writer");
    tcase_add_test(tc, objects_and_arrays_have_commas_between_values_only);
    tcase_add_test(tc, strings_escape_quotes_backslashes_and_control_characters);
    tcase_add_test(tc, numbers_are_written_as_the_device_writes_them);
    tcase_add_test(tc, a_long_text_grows_the_buffer);
    tcase_add_test(tc, a_raw_prefix_stands_before_the_json);
    suite_add_tcase(s, tc);
    SRunner *sr = srunner_create(s);
    srunner_run_all(sr, CK_NORMAL);
    int failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
