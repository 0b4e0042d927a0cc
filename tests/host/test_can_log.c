/* SPDX-License-Identifier: BSD-3-Clause */
/* The --can-log writer (host/can/can_log.c): candump -L lines of the frames it
 * is fed, standard and extended IDs and remote frames; reopening appends
 * to the path; a closed log takes frames and writes nothing. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "can_log.h"
#include "host_suites.h"

#define PATH_TEMPLATE "/tmp/can_log_test_XXXXXX"

static char path[sizeof(PATH_TEMPLATE)];

static void setup(void)
{
    memcpy(path, PATH_TEMPLATE, sizeof(path));
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
}

static void teardown(void)
{
    unlink(path);
}

static hal_can_frame_t frame(uint32_t id, uint8_t flags, uint8_t dlc)
{
    hal_can_frame_t f;
    memset(&f, 0, sizeof(f));
    f.id = id;
    f.flags = flags;
    f.dlc = dlc;
    for (uint8_t i = 0; i < dlc; i++) {
        f.data[i] = (uint8_t)(0xA0u + i);
    }
    return f;
}

START_TEST(frames_become_candump_lines)
{
    can_log_t log = {0};
    ck_assert(can_log_open(&log, path));
    hal_can_frame_t std = frame(0x123, 0, 2);
    hal_can_frame_t ext = frame(0x1ABCDE, HAL_CAN_FLAG_EXT, 0);
    hal_can_frame_t rtr = frame(0x7FF, HAL_CAN_FLAG_RTR, 4);
    can_log_frame(&log, &std, 1500000u);
    can_log_frame(&log, &ext, 2000001u);
    can_log_frame(&log, &rtr, 3000000u);
    can_log_close(&log);
    ck_assert_str_eq(t_read_all(path), "(0000000001.500000) " CAN_LOG_IFACE " 123#A0A1\n"
                                       "(0000000002.000001) " CAN_LOG_IFACE " 001ABCDE#\n"
                                       "(0000000003.000000) " CAN_LOG_IFACE " 7FF#R4\n");
}
END_TEST

/* After logrotate moved the file, the path is opened again and appended to. */
START_TEST(reopen_appends_to_the_path)
{
    can_log_t log = {0};
    char moved[sizeof(path) + 4];
    snprintf(moved, sizeof(moved), "%s.1", path);
    hal_can_frame_t f = frame(0x10, 0, 1);
    ck_assert(can_log_open(&log, path));
    can_log_frame(&log, &f, 0);
    ck_assert_int_eq(rename(path, moved), 0);
    ck_assert(can_log_reopen(&log));
    can_log_frame(&log, &f, 1);
    can_log_close(&log);
    ck_assert_str_eq(t_read_all(moved), "(0000000000.000000) " CAN_LOG_IFACE " 010#A0\n");
    ck_assert_str_eq(t_read_all(path), "(0000000000.000001) " CAN_LOG_IFACE " 010#A0\n");
    unlink(moved);
}
END_TEST

START_TEST(a_closed_log_writes_nothing)
{
    can_log_t log = {0};
    hal_can_frame_t f = frame(0x10, 0, 1);
    can_log_frame(&log, &f, 0);
    ck_assert(can_log_reopen(&log));
    can_log_close(&log);
    ck_assert_str_eq(t_read_all(path), "");
}
END_TEST

Suite *can_log_suite(void)
{
    Suite *s = suite_create("can_log");
    TCase *tc = tcase_create("candump");
    tcase_add_checked_fixture(tc, setup, teardown);
    tcase_add_test(tc, frames_become_candump_lines);
    tcase_add_test(tc, reopen_appends_to_the_path);
    tcase_add_test(tc, a_closed_log_writes_nothing);
    suite_add_tcase(s, tc);
    return s;
}
