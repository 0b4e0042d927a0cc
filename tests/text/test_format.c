/* SPDX-License-Identifier: BSD-3-Clause */
/* textbuf: the number and vector formatting every reply line uses. */
#include <check.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "unit_suites.h"
#include "wsg/wsg_textbuf.h"

static char storage[128];
static wsg_textbuf_t tb;

static const char *fmt_float(float value)
{
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_float(&tb, value);
    ck_assert(!tb.overflow);
    return storage;
}

static const char *fmt_int(int32_t value)
{
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_int(&tb, value);
    return storage;
}

/* The same text, written into a plain buffer (the float replies use it). */
static void expect_formatted(float value, const char *text)
{
    char out[WSG_TEXTBUF_FLOAT_MAX + 1];
    size_t len = wsg_textbuf_format_float(out, value);
    ck_assert_uint_le(len, WSG_TEXTBUF_FLOAT_MAX);
    out[len] = '\0';
    ck_assert_str_eq(out, text);
}

START_TEST(format_float_into_a_plain_buffer)
{
    expect_formatted(0.0f, "0.0");
    expect_formatted(-0.0004f, "0.0");
    expect_formatted(20.05f, "20.05");
    expect_formatted(1.02f, "1.02");
    expect_formatted(0.0015f, "0.002");
    expect_formatted(12.345f, "12.345");
    expect_formatted(99.5f, "99.5");
    expect_formatted(-3.125f, "-3.125");
    expect_formatted(-1e13f, "-1000000000000.0"); /* the longest: WSG_TEXTBUF_FLOAT_MAX */
}
END_TEST

START_TEST(float_one_decimal_minimum)
{
    ck_assert_str_eq(fmt_float(20.0f), "20.0");
    ck_assert_str_eq(fmt_float(0.0f), "0.0");
    ck_assert_str_eq(fmt_float(110.0f), "110.0");
    ck_assert_str_eq(fmt_float(142.0f), "142.0");
}
END_TEST

START_TEST(float_up_to_three_decimals)
{
    ck_assert_str_eq(fmt_float(20.05f), "20.05");
    ck_assert_str_eq(fmt_float(34.2f), "34.2");
    ck_assert_str_eq(fmt_float(0.001f), "0.001");
    ck_assert_str_eq(fmt_float(1.5f), "1.5");
    ck_assert_str_eq(fmt_float(12.345f), "12.345");
    ck_assert_str_eq(fmt_float(0.1f), "0.1");
    ck_assert_str_eq(fmt_float(0.01f), "0.01");
}
END_TEST

START_TEST(float_rounds_to_nearest_thousandth)
{
    ck_assert_str_eq(fmt_float(0.0004f), "0.0");
    ck_assert_str_eq(fmt_float(0.0006f), "0.001");
    ck_assert_str_eq(fmt_float(0.0015f), "0.002");
    ck_assert_str_eq(fmt_float(1.9996f), "2.0");
    ck_assert_str_eq(fmt_float(9.9999f), "10.0");
    ck_assert_str_eq(fmt_float(20.0499f), "20.05");
    ck_assert_str_eq(fmt_float(3.14159f), "3.142");
}
END_TEST

START_TEST(float_negative)
{
    ck_assert_str_eq(fmt_float(-3.0f), "-3.0");
    ck_assert_str_eq(fmt_float(-3.125f), "-3.125");
    ck_assert_str_eq(fmt_float(-0.001f), "-0.001");
    ck_assert_str_eq(fmt_float(-20.05f), "-20.05");
}
END_TEST

START_TEST(float_never_negative_zero)
{
    ck_assert_str_eq(fmt_float(-0.0f), "0.0");
    ck_assert_str_eq(fmt_float(-0.0004f), "0.0");
    ck_assert_str_eq(fmt_float(-1e-9f), "0.0");
}
END_TEST

START_TEST(float_large_values)
{
    ck_assert_str_eq(fmt_float(123456.789f), "123456.789");
    ck_assert_str_eq(fmt_float(16777216.0f), "16777216.0");
    ck_assert_str_eq(fmt_float(-4000000.5f), "-4000000.5");
}
END_TEST

START_TEST(float_saturates_without_exponent)
{
    ck_assert_str_eq(fmt_float(1e20f), "1000000000000.0");
    ck_assert_str_eq(fmt_float(-1e20f), "-1000000000000.0");
    ck_assert_str_eq(fmt_float(INFINITY), "1000000000000.0");
    ck_assert_str_eq(fmt_float(-FLT_MAX), "-1000000000000.0");
}
END_TEST

START_TEST(float_nan_is_zero)
{
    ck_assert_str_eq(fmt_float(NAN), "0.0");
}
END_TEST

/* The rule of the float text, with the C library's digits: |value| in
 * thousandths, rounded half up in double and saturated at 1e12, its whole
 * part, then one to three decimals without trailing zeros. */
static void reference_text(char *out, size_t cap, float value)
{
    double magnitude = fabs((double)value);
    magnitude = isnan(magnitude) ? 0.0 : fmin(magnitude, 1.0e12);
    unsigned long long millis = (unsigned long long)(magnitude * 1000.0 + 0.5);
    char decimals[4];
    snprintf(decimals, sizeof(decimals), "%03llu", millis % 1000u);
    for (int last = 2; last > 0 && decimals[last] == '0'; last--) {
        decimals[last] = '\0';
    }
    snprintf(out, cap, "%s%llu.%s", value < 0.0f && millis != 0u ? "-" : "", millis / 1000u,
             decimals);
}

static void expect_reference(float value)
{
    char expected[64];
    char out[WSG_TEXTBUF_FLOAT_MAX + 1];
    reference_text(expected, sizeof(expected), value);
    size_t len = wsg_textbuf_format_float(out, value);
    out[len] = '\0';
    if (strcmp(out, expected) != 0) { /* asserted only then: a million values */
        ck_assert_msg(0, "%.9g: \"%s\", the rule says \"%s\"", (double)value, out, expected);
    }
}

/* Every whole part up to beyond 1000 and every decimal (a stride prime to
 * 1000), both signs, and values across every magnitude. */
START_TEST(float_matches_the_rule_everywhere)
{
    for (uint32_t millis = 0; millis <= 1200000u; millis += 7u) {
        expect_reference((float)millis / 1000.0f);
        expect_reference(-(float)millis / 1000.0f);
    }
    uint32_t seed = 99u;
    for (int i = 0; i < 100000; i++) {
        seed = seed * 1664525u + 1013904223u;
        float value = ldexpf((float)(seed >> 8) / 16777216.0f, (int)(seed % 60u) - 20);
        expect_reference((seed & 1u) != 0u ? -value : value);
    }
}
END_TEST

START_TEST(integers)
{
    ck_assert_str_eq(fmt_int(0), "0");
    ck_assert_str_eq(fmt_int(-3), "-3");
    ck_assert_str_eq(fmt_int(12345678), "12345678");
    ck_assert_str_eq(fmt_int(INT32_MAX), "2147483647");
    ck_assert_str_eq(fmt_int(INT32_MIN), "-2147483648");
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_uint(&tb, UINT32_MAX);
    ck_assert_str_eq(storage, "4294967295");
}
END_TEST

START_TEST(bits_vector)
{
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_bits(&tb, 0x5u, 4);
    ck_assert_str_eq(storage, "[1,0,1,0]");
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_bits(&tb, 0x80000001u, 32);
    ck_assert_uint_eq(strlen(storage), 2 + 32 + 31);
    ck_assert(strncmp(storage, "[1,0,", 5) == 0);
    ck_assert_str_eq(storage + strlen(storage) - 3, ",1]");
}
END_TEST

START_TEST(quoted)
{
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, "DEVTYPE=");
    wsg_textbuf_put_quoted(&tb, "WSG 50-110");
    ck_assert_str_eq(storage, "DEVTYPE=\"WSG 50-110\"");
}
END_TEST

START_TEST(overflow_is_bounded_and_flagged)
{
    char small[8];
    memset(small, 'z', sizeof(small));
    wsg_textbuf_init(&tb, small, 6);
    wsg_textbuf_put_str(&tb, "ABCDEFGHIJ");
    ck_assert(tb.overflow);
    ck_assert_uint_eq(tb.len, 5);
    ck_assert_str_eq(small, "ABCDE");
    ck_assert_int_eq(small[6], 'z'); /* nothing written past cap */
}
END_TEST

START_TEST(exact_fit_is_not_overflow)
{
    char small[5];
    wsg_textbuf_init(&tb, small, sizeof(small));
    wsg_textbuf_put_str(&tb, "ABCD");
    ck_assert(!tb.overflow);
    ck_assert_str_eq(small, "ABCD");
}
END_TEST

Suite *format_suite(void)
{
    Suite *s = suite_create("format");
    TCase *floats = tcase_create("float");
    tcase_add_test(floats, float_one_decimal_minimum);
    tcase_add_test(floats, float_up_to_three_decimals);
    tcase_add_test(floats, float_rounds_to_nearest_thousandth);
    tcase_add_test(floats, float_negative);
    tcase_add_test(floats, float_never_negative_zero);
    tcase_add_test(floats, float_large_values);
    tcase_add_test(floats, float_saturates_without_exponent);
    tcase_add_test(floats, float_nan_is_zero);
    tcase_add_test(floats, float_matches_the_rule_everywhere);
    suite_add_tcase(s, floats);

    TCase *other = tcase_create("other");
    tcase_add_test(other, integers);
    tcase_add_test(other, bits_vector);
    tcase_add_test(other, quoted);
    tcase_add_test(other, overflow_is_bounded_and_flagged);
    tcase_add_test(other, format_float_into_a_plain_buffer);
    tcase_add_test(other, exact_fit_is_not_overflow);
    suite_add_tcase(s, other);
    return s;
}
