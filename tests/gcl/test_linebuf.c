/* SPDX-License-Identifier: BSD-3-Clause */
/* gcl_linebuf: assembling a byte stream into lines, and how the device
 * answers lines the assembler flags. */
#include <check.h>
#include <stdio.h>
#include <string.h>

#include "wsg/gcl_linebuf.h"
#include "fake_device.h"
#include "unit_suites.h"

static gcl_linebuf_t lb;

static void lb_setup(void)
{
    wsg_gcl_linebuf_reset(&lb);
}

/* Feeds bytes; returns how many lines completed, the last one left in lb. */
static unsigned feed(const char *bytes, size_t len)
{
    unsigned lines = 0;
    for (size_t i = 0; i < len; i++) {
        if (wsg_gcl_linebuf_feed(&lb, (uint8_t)bytes[i])) {
            lines++;
        }
    }
    return lines;
}

static unsigned feed_str(const char *s)
{
    return feed(s, strlen(s));
}

static void fill(char *buf, size_t n, char c)
{
    memset(buf, c, n);
    buf[n] = '\0';
}

START_TEST(split_across_feeds)
{
    ck_assert_uint_eq(feed_str("HO"), 0);
    ck_assert(wsg_gcl_linebuf_pending(&lb));
    ck_assert_uint_eq(feed_str("ME("), 0);
    ck_assert_uint_eq(feed_str(")\n"), 1);
    ck_assert_str_eq(lb.text, "HOME()");
    ck_assert_uint_eq(lb.len, 6);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
    ck_assert(!wsg_gcl_linebuf_pending(&lb));
}
END_TEST

START_TEST(crlf_is_stripped)
{
    ck_assert_uint_eq(feed_str("POS?\r\n"), 1);
    ck_assert_str_eq(lb.text, "POS?");
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
}
END_TEST

/* manual 1.2: 0x0d terminates a command as well */
START_TEST(cr_alone_ends_a_line)
{
    ck_assert_uint_eq(feed_str("POS?\r"), 1);
    ck_assert_str_eq(lb.text, "POS?");
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
    ck_assert_uint_eq(feed_str("SN?\rTAG?\r"), 2);
    ck_assert_str_eq(lb.text, "TAG?");
}
END_TEST

/* "\r\n" is one line end, also when a write ends between its two bytes */
START_TEST(crlf_split_across_feeds_is_one_end)
{
    ck_assert_uint_eq(feed_str("POS?\r"), 1);
    ck_assert_uint_eq(feed_str("\n"), 0);
    ck_assert(!wsg_gcl_linebuf_pending(&lb));
    ck_assert_uint_eq(feed_str("SN?\r"), 1);
    ck_assert_uint_eq(feed_str("\nTAG?\n"), 1);
    ck_assert_str_eq(lb.text, "TAG?");
}
END_TEST

START_TEST(lf_cr_is_two_ends)
{
    ck_assert_uint_eq(feed_str("POS?\n\r"), 2);
    ck_assert_uint_eq(lb.len, 0);
}
END_TEST

START_TEST(next_line_starts_fresh)
{
    ck_assert_uint_eq(feed_str("A\x01\n"), 1);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_BAD_BYTE);
    ck_assert_uint_eq(feed_str("B\n"), 1);
    ck_assert_str_eq(lb.text, "B");
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
}
END_TEST

START_TEST(empty_line)
{
    ck_assert_uint_eq(feed_str("\n"), 1);
    ck_assert_uint_eq(lb.len, 0);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
    ck_assert_uint_eq(feed_str("\r\n"), 1);
    ck_assert_uint_eq(lb.len, 0);
}
END_TEST

START_TEST(cr_inside_splits_the_line)
{
    ck_assert_uint_eq(feed_str("PO\rS?\n"), 2);
    ck_assert_str_eq(lb.text, "S?");
    ck_assert_uint_eq(feed_str("POS?\r\r\n"), 2); /* "POS?" and an empty line */
    ck_assert_uint_eq(lb.len, 0);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
}
END_TEST

START_TEST(tab_is_allowed)
{
    ck_assert_uint_eq(feed_str("\tPOS?\t\n"), 1);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
    ck_assert_str_eq(lb.text, "\tPOS?\t");
}
END_TEST

START_TEST(bad_bytes)
{
    static const uint8_t bad[] = {0x00, 0x01, 0x1b, 0x7f, 0x80, 0xc3, 0xff};
    for (size_t i = 0; i < sizeof(bad); i++) {
        wsg_gcl_linebuf_reset(&lb);
        feed_str("PO");
        ck_assert(!wsg_gcl_linebuf_feed(&lb, bad[i]));
        ck_assert_uint_eq(feed_str("S?\n"), 1);
        ck_assert_msg(wsg_gcl_linebuf_status(&lb) == GCL_LINE_BAD_BYTE, "byte 0x%02x", bad[i]);
        ck_assert_str_eq(lb.text, "POS?"); /* the bad byte is not stored */
    }
}
END_TEST

START_TEST(longest_line)
{
    char line[GCL_LINE_MAX + 2];
    fill(line, GCL_LINE_MAX, 'a');
    strcat(line, "\n");
    ck_assert_uint_eq(feed_str(line), 1);
    ck_assert_uint_eq(lb.len, GCL_LINE_MAX);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
}
END_TEST

START_TEST(longest_line_with_crlf)
{
    /* the '\r' is part of the terminator, not of the line */
    char line[GCL_LINE_MAX + 3];
    fill(line, GCL_LINE_MAX, 'a');
    strcat(line, "\r\n");
    ck_assert_uint_eq(feed_str(line), 1);
    ck_assert_uint_eq(lb.len, GCL_LINE_MAX);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
}
END_TEST

START_TEST(full_line_then_one_more_is_too_long)
{
    char line[GCL_LINE_MAX + 4];
    fill(line, GCL_LINE_MAX, 'a');
    strcat(line, "b\r\n");
    ck_assert_uint_eq(feed_str(line), 1);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_TOO_LONG);
    ck_assert_uint_eq(lb.len, GCL_LINE_MAX);
    ck_assert_uint_eq(strlen(lb.text), GCL_LINE_MAX);
}
END_TEST

START_TEST(too_long_then_resync)
{
    char line[GCL_LINE_MAX + 3];
    fill(line, GCL_LINE_MAX + 1, 'a');
    strcat(line, "\n");
    ck_assert_uint_eq(feed_str(line), 1);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_TOO_LONG);
    ck_assert_uint_eq(lb.len, GCL_LINE_MAX); /* the first bytes are kept */
    ck_assert_uint_eq(strlen(lb.text), GCL_LINE_MAX);
    ck_assert_uint_eq(feed_str("POS?\n"), 1);
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_OK);
    ck_assert_str_eq(lb.text, "POS?");
}
END_TEST

START_TEST(very_long_line_is_bounded)
{
    for (unsigned i = 0; i < 10000; i++) {
        ck_assert(!wsg_gcl_linebuf_feed(&lb, 'x'));
    }
    ck_assert(wsg_gcl_linebuf_pending(&lb));
    ck_assert(wsg_gcl_linebuf_feed(&lb, '\n'));
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_TOO_LONG);
    ck_assert_uint_eq(lb.len, GCL_LINE_MAX);
}
END_TEST

START_TEST(flush)
{
    ck_assert(!wsg_gcl_linebuf_flush(&lb));
    feed_str("POS?");
    ck_assert(wsg_gcl_linebuf_flush(&lb));
    ck_assert_str_eq(lb.text, "POS?");
    ck_assert(!wsg_gcl_linebuf_pending(&lb));
    ck_assert(!wsg_gcl_linebuf_flush(&lb));
}
END_TEST

START_TEST(flush_of_a_bad_byte_alone)
{
    wsg_gcl_linebuf_feed(&lb, 0x00);
    ck_assert(wsg_gcl_linebuf_pending(&lb));
    ck_assert(wsg_gcl_linebuf_flush(&lb));
    ck_assert_int_eq(wsg_gcl_linebuf_status(&lb), GCL_LINE_BAD_BYTE);
}
END_TEST

/* The bulk feed hands out the same lines, with the same status and text, as
 * feeding the bytes one at a time, whatever the bytes and however they are
 * split. */
static void expect_bulk_matches_bytewise(const uint8_t *bytes, size_t len, size_t chunk)
{
    gcl_linebuf_t one;
    gcl_linebuf_t bulk;
    wsg_gcl_linebuf_reset(&one);
    wsg_gcl_linebuf_reset(&bulk);
    size_t i = 0;
    for (size_t at = 0; at < len; at += chunk) {
        size_t end = at + chunk < len ? at + chunk : len;
        size_t j = at;
        while (j < end) {
            bool done = false;
            j += wsg_gcl_linebuf_feed_bytes(&bulk, bytes + j, end - j, &done);
            bool one_done = false;
            while (i < j && !one_done) {
                one_done = wsg_gcl_linebuf_feed(&one, bytes[i++]);
            }
            ck_assert_uint_eq(i, j);
            ck_assert(done == one_done);
            ck_assert_uint_eq(bulk.len, one.len);
            ck_assert(memcmp(bulk.text, one.text, one.len) == 0);
            if (done) {
                ck_assert_int_eq(wsg_gcl_linebuf_status(&bulk), wsg_gcl_linebuf_status(&one));
                ck_assert_str_eq(bulk.text, one.text);
            }
        }
    }
    ck_assert(wsg_gcl_linebuf_pending(&bulk) == wsg_gcl_linebuf_pending(&one));
    ck_assert(wsg_gcl_linebuf_flush(&bulk) == wsg_gcl_linebuf_flush(&one));
    ck_assert_int_eq(wsg_gcl_linebuf_status(&bulk), wsg_gcl_linebuf_status(&one));
    ck_assert_str_eq(bulk.text, one.text);
}

START_TEST(bulk_feed_matches_bytewise)
{
    static const char *const texts[] = {
        "POS?\nPOS?\r\nSPEED?\rFORCE?\n\n\r\r\n\r",
        "MOVE(\x01 20)\nGRIP(\t20 ,\x7f 10)\r\n\xff\xfe\n",
        "\r\n\n\r\r\rPOS?",
    };
    uint8_t bytes[3 * GCL_LINE_MAX];
    for (size_t k = 0; k < sizeof(texts) / sizeof(texts[0]); k++) {
        for (size_t chunk = 1; chunk <= 7; chunk++) {
            expect_bulk_matches_bytewise((const uint8_t *)texts[k], strlen(texts[k]), chunk);
        }
    }
    /* lines around and beyond the longest, with and without a bad byte */
    memset(bytes, 'A', sizeof(bytes));
    bytes[GCL_LINE_MAX] = '\n';
    bytes[2 * GCL_LINE_MAX + 1] = '\r';
    bytes[2 * GCL_LINE_MAX + 2] = '\n';
    bytes[2 * GCL_LINE_MAX + 5] = 0x00;
    for (size_t chunk = 1; chunk <= sizeof(bytes); chunk += 37) {
        expect_bulk_matches_bytewise(bytes, sizeof(bytes), chunk);
    }
    /* every byte value, in a pseudo-random order and split */
    uint32_t seed = 12345u;
    for (int round = 0; round < 50; round++) {
        for (size_t i = 0; i < 200; i++) {
            seed = seed * 1103515245u + 12345u;
            uint8_t b = (uint8_t)(seed >> 16);
            bytes[i] = (seed >> 28) < 3u ? (uint8_t) "\n\r\t"[seed >> 28] : b;
        }
        expect_bulk_matches_bytewise(bytes, 200, 1u + (size_t)round % 13u);
    }
}
END_TEST

/* Whether two buffers hold the same state: what a later feed, flush or
 * status reads (the text up to its length and its NUL). */
static void expect_same_state(const gcl_linebuf_t *a, const gcl_linebuf_t *b)
{
    ck_assert_uint_eq(a->len, b->len);
    ck_assert(a->too_long == b->too_long && a->bad_byte == b->bad_byte);
    ck_assert(a->complete == b->complete && a->ended_by_cr == b->ended_by_cr);
    ck_assert(memcmp(a->text, b->text, a->len + 1u) == 0);
}

/* After prefix, take_line takes input's known line exactly when feeding the
 * bytes one at a time completes that line, OK, with its line end as the
 * next byte, and leaves the buffer as that feed does; else it takes nothing
 * and changes nothing. */
static void expect_take_matches_feed(const char *prefix, const char *input, const char *line)
{
    gcl_linebuf_t fed;
    gcl_linebuf_t taken;
    wsg_gcl_linebuf_reset(&fed);
    for (size_t i = 0; prefix[i] != '\0'; i++) {
        (void)wsg_gcl_linebuf_feed(&fed, (uint8_t)prefix[i]);
    }
    taken = fed;
    gcl_linebuf_t before = fed;
    size_t len = strlen(input);
    size_t consumed = 0;
    bool done = false;
    while (consumed < len && !done) {
        done = wsg_gcl_linebuf_feed(&fed, (uint8_t)input[consumed++]);
    }
    bool same_line = done && consumed == strlen(line) + 1u &&
                     wsg_gcl_linebuf_status(&fed) == GCL_LINE_OK && strcmp(fed.text, line) == 0;
    size_t n = wsg_gcl_linebuf_take_line(&taken, (const uint8_t *)input, len, line, strlen(line));
    ck_assert_msg(n == (same_line ? consumed : 0u), "after \"%s\", \"%s\" for \"%s\": took %zu",
                  prefix, input, line, n);
    expect_same_state(&taken, same_line ? &fed : &before);
}

START_TEST(take_line_matches_bytewise)
{
    static char long_line[GCL_LINE_MAX + 8];
    fill(long_line, GCL_LINE_MAX + 5, 'A');
    char long_ended[sizeof(long_line) + 1];
    snprintf(long_ended, sizeof(long_ended), "%s\n", long_line);
    const char *const prefixes[] = {"",   "TAG?\n", "TAG?\r", "TAG?\r\n", "PO",      "\x01",
                                    "\r", "\n",     "\x01\n", long_line,  long_ended};
    static const char *const inputs[] = {
        "POS?\n",     "POS?\r",         "POS?\r\n",    "\nPOS?\n", "POS?", "POS? \n",
        "POS?x\n",    "pos?\n",         "POS",         "",         "\n",   "\tPOS ?\n",
        "POS?\x01\n", "SPEED?\nPOS?\n", "POSITION?\n", "PO\nS?\n"};
    static const char *const lines[] = {"POS?", "\tPOS ?", "pos?", "SPEED?", "P"};
    for (size_t p = 0; p < sizeof(prefixes) / sizeof(prefixes[0]); p++) {
        for (size_t i = 0; i < sizeof(inputs) / sizeof(inputs[0]); i++) {
            for (size_t l = 0; l < sizeof(lines) / sizeof(lines[0]); l++) {
                expect_take_matches_feed(prefixes[p], inputs[i], lines[l]);
            }
        }
    }
    /* every length up to the longest line a connection remembers, and beyond;
     * a last byte that differs */
    char known[GCL_LINE_MAX + 1];
    char input[GCL_LINE_MAX + 3];
    for (size_t n = 1; n <= 26; n++) {
        fill(known, n, 'Q');
        snprintf(input, sizeof(input), "%s\r\n", known);
        expect_take_matches_feed("", input, known);
        expect_take_matches_feed("TAG?\r", input, known);
        input[n - 1] = 'R';
        expect_take_matches_feed("", input, known);
        input[0] = 'R';
        input[n - 1] = 'Q';
        expect_take_matches_feed("", input, known);
    }
}
END_TEST

/* --- through a session --- */

START_TEST(device_split_bytes)
{
    const char *text = "POS?\n";
    for (size_t i = 0; text[i] != '\0'; i++) {
        EXPECT_NONE();
        h_send_bytes(&h_main, &text[i], 1);
    }
    EXPECT("POS=55.0");
    EXPECT_NONE();
}
END_TEST

START_TEST(device_several_lines_in_one_feed)
{
    const char *text = "POS?\r\nGRIPSTATE?\nSN?\n";
    h_send_bytes(&h_main, text, strlen(text));
    EXPECT("POS=55.0");
    EXPECT("GRIPSTATE=0");
    EXPECT("SN=12345678");
    EXPECT_NONE();
}
END_TEST

/* a client ending lines with "\r\n" in two writes gets one reply per line,
 * and the device counts no extra (empty) lines */
START_TEST(device_crlf_in_two_writes)
{
    h_send_bytes(&h_main, "POS?\r", 5);
    EXPECT("POS=55.0");
    h_send_bytes(&h_main, "\n", 1);
    h_send_bytes(&h_main, "SN?\r", 4);
    EXPECT("SN=12345678");
    EXPECT_NONE();
    ck_assert_uint_eq(h_gcl_lines_in(&h_main), 2);
}
END_TEST

START_TEST(device_cr_terminated_commands)
{
    const char *text = "VERBOSE=1\rPOS?\r";
    h_send_bytes(&h_main, text, strlen(text));
    EXPECT("VERBOSE=1");
    EXPECT("POS=55.0");
    EXPECT_NONE();
}
END_TEST

START_TEST(device_ignores_blank_lines)
{
    const char *text = "\n\r\n  \t \nPOS?\n";
    h_send_bytes(&h_main, text, strlen(text));
    EXPECT("POS=55.0");
    EXPECT_NONE();
}
END_TEST

START_TEST(device_bad_byte_with_name)
{
    const uint8_t text[] = {'P', 'O', 'S', 0x00, '?', '\n', 'P', 'O', 'S', '?', '\n'};
    h_send_bytes(&h_main, text, sizeof(text));
    EXPECT("ERR POS 15");
    EXPECT("POS=55.0");
    EXPECT_NONE();
}
END_TEST

START_TEST(device_bad_byte_without_name)
{
    const uint8_t text[] = {0x80, 0xff, '\n', 0x07, '\n', 'S', 'N', '?', '\n'};
    h_send_bytes(&h_main, text, sizeof(text));
    EXPECT("ERR ? 15");
    EXPECT("ERR ? 15");
    EXPECT("SN=12345678");
    EXPECT_NONE();
}
END_TEST

START_TEST(device_utf8_in_argument)
{
    send_line(&h_main, "AUTOSEND(\"P\xc3\x96S\",10)");
    EXPECT("ERR AUTOSEND 15");
    EXPECT_NONE();
}
END_TEST

START_TEST(device_longest_line)
{
    char line[GCL_LINE_MAX + 1];
    fill(line, GCL_LINE_MAX, ' ');
    memcpy(line, "POS", 3);
    line[GCL_LINE_MAX - 1] = '?';
    ASK_EQ(line, "POS=55.0");
}
END_TEST

START_TEST(device_longest_line_with_crlf)
{
    char line[GCL_LINE_MAX + 3];
    fill(line, GCL_LINE_MAX, ' ');
    memcpy(line, "SN", 2);
    line[GCL_LINE_MAX - 1] = '?';
    strcat(line, "\r\n");
    h_send_bytes(&h_main, line, strlen(line));
    EXPECT("SN=12345678");
    EXPECT_NONE();
}
END_TEST

START_TEST(device_too_long_then_resync)
{
    char line[GCL_LINE_MAX + 2];
    fill(line, GCL_LINE_MAX + 1, ' ');
    memcpy(line, "POS", 3);
    line[GCL_LINE_MAX] = '?';
    ASK_EQ(line, "ERR POS 15");
    ASK_EQ("POS?", "POS=55.0");
}
END_TEST

START_TEST(device_too_long_without_name)
{
    char line[600];
    fill(line, sizeof(line) - 1, '1');
    ASK_EQ(line, "ERR ? 15");
    ASK_EQ("SN?", "SN=12345678");
}
END_TEST

Suite *linebuf_suite(void)
{
    Suite *s = suite_create("linebuf");
    TCase *unit = tcase_create("assembler");
    tcase_add_checked_fixture(unit, lb_setup, NULL);
    tcase_add_test(unit, split_across_feeds);
    tcase_add_test(unit, crlf_is_stripped);
    tcase_add_test(unit, next_line_starts_fresh);
    tcase_add_test(unit, empty_line);
    tcase_add_test(unit, cr_alone_ends_a_line);
    tcase_add_test(unit, crlf_split_across_feeds_is_one_end);
    tcase_add_test(unit, lf_cr_is_two_ends);
    tcase_add_test(unit, cr_inside_splits_the_line);
    tcase_add_test(unit, tab_is_allowed);
    tcase_add_test(unit, bad_bytes);
    tcase_add_test(unit, longest_line);
    tcase_add_test(unit, longest_line_with_crlf);
    tcase_add_test(unit, full_line_then_one_more_is_too_long);
    tcase_add_test(unit, too_long_then_resync);
    tcase_add_test(unit, very_long_line_is_bounded);
    tcase_add_test(unit, flush);
    tcase_add_test(unit, flush_of_a_bad_byte_alone);
    tcase_add_test(unit, bulk_feed_matches_bytewise);
    tcase_add_test(unit, take_line_matches_bytewise);
    suite_add_tcase(s, unit);

    TCase *device = tcase_create("device");
    tcase_add_checked_fixture(device, h_setup, h_teardown);
    tcase_add_test(device, device_split_bytes);
    tcase_add_test(device, device_several_lines_in_one_feed);
    tcase_add_test(device, device_crlf_in_two_writes);
    tcase_add_test(device, device_cr_terminated_commands);
    tcase_add_test(device, device_ignores_blank_lines);
    tcase_add_test(device, device_bad_byte_with_name);
    tcase_add_test(device, device_bad_byte_without_name);
    tcase_add_test(device, device_utf8_in_argument);
    tcase_add_test(device, device_longest_line);
    tcase_add_test(device, device_longest_line_with_crlf);
    tcase_add_test(device, device_too_long_then_resync);
    tcase_add_test(device, device_too_long_without_name);
    suite_add_tcase(s, device);
    return s;
}
