/* SPDX-License-Identifier: BSD-3-Clause */
/* Requests that need no motion: framing errors in their documented order,
 * queries, settings shared with GCL, system and finger commands. */
#include <string.h>

#include "fake_bin_conn.h"
#include "sim_models.h"
#include "suites.h"
#include "wsg/wsg_bin.h"

static const wsg_config_t *cfg(void)
{
    return wsg_device_snapshot(&h_dev)->config;
}

START_TEST(unknown_id_is_cmd_unknown)
{
    bc_send(&bc_main, 0x90, NULL, 0);
    bc_expect(&bc_main, 0x90, E_CMD_UNKNOWN);
    bc_send(&bc_main, 0xB0, NULL, 0);
    bc_expect(&bc_main, 0xB0, E_CMD_UNKNOWN);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(bad_crc_echoes_the_id_and_runs_nothing)
{
    bc_send_crc(&bc_main, 0x23, NULL, 0, 0x1234);
    bc_expect(&bc_main, 0x23, E_CHECKSUM_ERROR);
    uint32_t flags = wsg_device_snapshot(&h_dev)->flags;
    ck_assert_uint_eq(flags & WSG_FLAG(SF_FAST_STOP), 0);
    ck_assert_uint_ne(flags & WSG_FLAG(SF_CMD_FAILURE), 0);
}
END_TEST

START_TEST(crc_off_setting_ignores_the_checksum)
{
    h_cfg()->bin_crc_unchecked = true;
    bc_send_crc(&bc_main, 0x23, NULL, 0, 0x0000);
    bc_expect(&bc_main, 0x23, E_SUCCESS);
    ck_assert_int_eq(ask_flag(SF_FAST_STOP), 1);
}
END_TEST

START_TEST(wrong_lengths)
{
    const uint8_t extra = 1;
    bc_send(&bc_main, 0x31, &extra, 1);
    bc_expect(&bc_main, 0x31, E_NO_PARAM_EXPECTED);
    bc_send(&bc_main, 0x30, &extra, 1);
    bc_expect(&bc_main, 0x30, E_CMD_FORMAT_ERROR);
    bc_send(&bc_main, 0x43, &extra, 1);
    bc_expect(&bc_main, 0x43, E_CMD_FORMAT_ERROR);
    uint8_t big[300] = {0};
    bc_send(&bc_main, 0x06, big, sizeof(big));
    bc_expect(&bc_main, 0x06, E_CMD_FORMAT_ERROR);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(loop_echoes)
{
    const uint8_t data[] = {0xAA, 0xAA, 0xAA, 1, 2, 3};
    bc_send(&bc_main, 0x06, data, sizeof(data));
    const bc_frame_t *f = bc_expect(&bc_main, 0x06, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, sizeof(data));
    ck_assert_mem_eq(f->values, data, sizeof(data));
}
END_TEST

START_TEST(split_byte_by_byte_and_merged)
{
    uint8_t frames[64];
    size_t n = wsg_bin_encode_frame(frames, sizeof(frames), 0x31, NULL, 0);
    n += wsg_bin_encode_frame(frames + n, sizeof(frames) - n, 0x33, NULL, 0);
    const uint8_t noise[] = {0x00, 0xAA, 0x13};
    wsg_conn_input(&bc_main.conn, noise, sizeof(noise));
    for (size_t i = 0; i < n; i++) {
        wsg_conn_input(&bc_main.conn, frames + i, 1);
    }
    bc_expect(&bc_main, 0x31, E_SUCCESS);
    bc_expect(&bc_main, 0x33, E_SUCCESS);
    wsg_conn_input(&bc_main.conn, frames, n);
    bc_expect(&bc_main, 0x31, E_SUCCESS);
    bc_expect(&bc_main, 0x33, E_SUCCESS);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(acceleration_is_clamped_and_shared)
{
    uint8_t p[4];
    wsg_bin_put_f32(p, 1e9f);
    bc_send(&bc_main, 0x30, p, 4);
    bc_expect(&bc_main, 0x30, E_SUCCESS);
    bc_send(&bc_main, 0x31, NULL, 0);
    ck_assert_float_eq(bc_f32(bc_expect(&bc_main, 0x31, E_SUCCESS), 0), cfg()->accel_max_mm_s2);
    wsg_bin_put_f32(p, 0.0f);
    bc_send(&bc_main, 0x30, p, 4);
    bc_expect(&bc_main, 0x30, E_SUCCESS);
    ck_assert_float_eq(cfg()->default_accel_mm_s2, cfg()->accel_min_mm_s2);
}
END_TEST

START_TEST(force_limit_is_clamped_and_nan_refused)
{
    uint8_t p[4];
    wsg_bin_put_f32(p, 1e9f);
    bc_send(&bc_main, 0x32, p, 4);
    bc_expect(&bc_main, 0x32, E_SUCCESS);
    bc_send(&bc_main, 0x33, NULL, 0);
    ck_assert_float_eq(bc_f32(bc_expect(&bc_main, 0x33, E_SUCCESS), 0),
                       wsg_config_force_max(cfg()));
    wsg_bin_put_u32(p, 0x7FC00000u); /* NaN */
    bc_send(&bc_main, 0x32, p, 4);
    bc_expect(&bc_main, 0x32, E_INVALID_PARAMETER);
    ck_assert_float_eq(cfg()->default_force_n, wsg_config_force_max(cfg()));
}
END_TEST

START_TEST(soft_limits_set_get_clear)
{
    bc_send(&bc_main, 0x35, NULL, 0);
    bc_expect(&bc_main, 0x35, E_NOT_AVAILABLE);
    uint8_t p[8];
    wsg_bin_put_f32(p, 10.0f);
    wsg_bin_put_f32(p + 4, 90.0f);
    bc_send(&bc_main, 0x34, p, 8);
    bc_expect(&bc_main, 0x34, E_SUCCESS);
    bc_send(&bc_main, 0x35, NULL, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x35, E_SUCCESS);
    ck_assert_float_eq(bc_f32(f, 0), 10.0f);
    ck_assert_float_eq(bc_f32(f, 4), 90.0f);
    wsg_bin_put_f32(p, 95.0f); /* minus above plus */
    bc_send(&bc_main, 0x34, p, 8);
    bc_expect(&bc_main, 0x34, E_RANGE_ERROR);
    ck_assert_float_eq(cfg()->soft_limit_minus_mm, 10.0f);
    bc_send(&bc_main, 0x36, NULL, 0);
    bc_expect(&bc_main, 0x36, E_SUCCESS);
    ck_assert(!cfg()->soft_limits_enabled);
}
END_TEST

START_TEST(state_width_temperature_queries)
{
    bc_query(&bc_main, 0x40, 0, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x40, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 4);
    ck_assert_uint_eq(wsg_bin_get_u32(f->values), wsg_device_snapshot(&h_dev)->flags);
    bc_query(&bc_main, 0x41, 0, 0);
    f = bc_expect(&bc_main, 0x41, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 1);
    ck_assert_uint_eq(f->values[0], GS_IDLE);
    bc_query(&bc_main, 0x43, 0, 0);
    f = bc_expect(&bc_main, 0x43, E_SUCCESS);
    ck_assert_float_eq_tol(bc_f32(f, 0), ask_float("POS?"), 0.01f);
    bc_send(&bc_main, 0x46, NULL, 0);
    f = bc_expect(&bc_main, 0x46, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 2);
    float temp = wsg_device_snapshot(&h_dev)->temperature_c;
    ck_assert_int_eq((int16_t)wsg_bin_get_u16(f->values), (int)(temp * 10.0f + 0.5f));
}
END_TEST

START_TEST(statistics_and_reset)
{
    h_devp()->grip.stats[0] = 7;
    h_devp()->grip.stats[1] = 2;
    const uint8_t reset = 1;
    bc_send(&bc_main, 0x42, &reset, 1);
    const bc_frame_t *f = bc_expect(&bc_main, 0x42, E_SUCCESS);
    ck_assert_uint_eq(wsg_bin_get_u32(f->values), 7);
    ck_assert_uint_eq(wsg_bin_get_u16(f->values + 4), 2);
    ck_assert_uint_eq(h_devp()->grip.stats[0], 0);
}
END_TEST

START_TEST(system_info_tag_limits)
{
    bc_send(&bc_main, 0x50, NULL, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x50, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 8);
    ck_assert_uint_eq(f->values[0], 1); /* WSG 50 */
    ck_assert_uint_eq(f->values[1], cfg()->hw_revision);
    ck_assert_uint_eq(wsg_bin_get_u16(f->values + 2), 0x4000);
    ck_assert_uint_eq(wsg_bin_get_u32(f->values + 4), cfg()->serial);
    bc_send(&bc_main, 0x51, "cell-3\0\0", 8);
    bc_expect(&bc_main, 0x51, E_SUCCESS);
    ASK_EQ("TAG?", "TAG=\"cell-3\"");
    bc_send(&bc_main, 0x52, NULL, 0);
    f = bc_expect(&bc_main, 0x52, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 6);
    ck_assert_mem_eq(f->values, "cell-3", 6);
    bc_send(&bc_main, 0x53, NULL, 0);
    f = bc_expect(&bc_main, 0x53, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 32);
    ck_assert_float_eq(bc_f32(f, 0), cfg()->stroke_mm);
    ck_assert_float_eq(bc_f32(f, 8), cfg()->speed_max_mm_s);
}
END_TEST

static float limits_overdrive_field(void)
{
    bc_send(&bc_main, 0x53, NULL, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x53, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 32);
    ck_assert_float_eq(bc_f32(f, 24), cfg()->force_max_n);
    return bc_f32(f, 28);
}

/* 0x53's overdrive force is the nominal maximum on every model without an
 * overdrive mode (Drake clamps its force commands to it); a model with one
 * reports its own. */
START_TEST(limits_overdrive_force_is_never_zero)
{
    for (unsigned i = 0; i < wsg_sim_model_count(); i++) {
        const sim_model_t *model = wsg_sim_model_at(i);
        h_cfg()->force_max_n = model->force_max_n;
        h_cfg()->force_overdrive_n = model->force_overdrive_n;
        float expected =
            model->force_overdrive_n > 0.0f ? model->force_overdrive_n : model->force_max_n;
        ck_assert_msg(limits_overdrive_field() == expected, "%s", model->name);
        ck_assert_float_gt(expected, 0.0f);
    }
    h_cfg()->force_overdrive_n = 120.0f;
    ck_assert_float_eq(limits_overdrive_field(), 120.0f);
}
END_TEST

/* 0x51 with a byte that could forge a GCL reply: refused with
 * E_INVALID_PARAMETER, and the tag GCL's TAG? reads stays. */
START_TEST(set_tag_refuses_line_breaks_quotes_and_non_ascii)
{
    bc_send(&bc_main, 0x51, "cell-3", 6);
    bc_expect(&bc_main, 0x51, E_SUCCESS);
    static const char *const bad[] = {"a\nFIN HOME", "a\rFIN HOME", "a\" FIN", "bad \xff",
                                      "caf\xc3\xa9"};
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        bc_send(&bc_main, 0x51, bad[i], strlen(bad[i]));
        bc_expect(&bc_main, 0x51, E_INVALID_PARAMETER);
        ASK_EQ("TAG?", "TAG=\"cell-3\"");
    }
    bc_send(&bc_main, 0x51, "a\0b", 3); /* a NUL inside */
    bc_expect(&bc_main, 0x51, E_INVALID_PARAMETER);
    char long_tag[WSG_CONFIG_STRING_MAX];
    memset(long_tag, 'x', sizeof(long_tag));
    bc_send(&bc_main, 0x51, long_tag, sizeof(long_tag));
    bc_expect(&bc_main, 0x51, E_RANGE_ERROR);
    bc_send(&bc_main, 0x52, NULL, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x52, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 6);
    ck_assert_mem_eq(f->values, "cell-3", 6);
    bc_expect_none(&bc_main);
}
END_TEST

START_TEST(fingers_without_fingers)
{
    bc_send(&bc_main, 0x60, NULL, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x60, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 3);
    ck_assert_uint_eq(f->values[0], 255);
    bc_send(&bc_main, 0x73, NULL, 0);
    bc_expect(&bc_main, 0x73, E_NOT_AVAILABLE);
    bc_send(&bc_main, 0x71, NULL, 0);
    f = bc_expect(&bc_main, 0x71, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 2);
    const uint8_t index = 0;
    bc_send(&bc_main, 0x61, &index, 1);
    bc_expect(&bc_main, 0x61, E_NO_PARAM_EXPECTED);
    bc_send(&bc_main, 0x38, NULL, 0);
    bc_expect(&bc_main, 0x38, E_NOT_AVAILABLE);
}
END_TEST

START_TEST(fmf_finger_data_and_tare)
{
    h_setup_fmf_homed();
    bc_open(&bc_main, WSG_TRANSPORT_STREAM, &wsg_bin_driver);
    bc_send(&bc_main, 0x60, NULL, 0);
    const bc_frame_t *f = bc_expect(&bc_main, 0x60, E_SUCCESS);
    ck_assert_uint_eq(f->values[0], 1);
    ck_assert_uint_eq(wsg_bin_get_u16(f->values + 1), 4);
    bc_send(&bc_main, 0x63, NULL, 0);
    f = bc_expect(&bc_main, 0x63, E_SUCCESS);
    ck_assert_uint_eq(f->values_len, 4);
    bc_send(&bc_main, 0x38, NULL, 0);
    bc_expect(&bc_main, 0x38, E_SUCCESS);
}
END_TEST

Suite *bin_requests_suite(void)
{
    Suite *s = suite_create("bin_requests");
    TCase *tc = tcase_create("requests");
    tcase_add_checked_fixture(tc, bc_setup, bc_teardown);
    tcase_add_test(tc, unknown_id_is_cmd_unknown);
    tcase_add_test(tc, bad_crc_echoes_the_id_and_runs_nothing);
    tcase_add_test(tc, crc_off_setting_ignores_the_checksum);
    tcase_add_test(tc, wrong_lengths);
    tcase_add_test(tc, loop_echoes);
    tcase_add_test(tc, split_byte_by_byte_and_merged);
    tcase_add_test(tc, acceleration_is_clamped_and_shared);
    tcase_add_test(tc, force_limit_is_clamped_and_nan_refused);
    tcase_add_test(tc, soft_limits_set_get_clear);
    tcase_add_test(tc, state_width_temperature_queries);
    tcase_add_test(tc, statistics_and_reset);
    tcase_add_test(tc, system_info_tag_limits);
    tcase_add_test(tc, limits_overdrive_force_is_never_zero);
    tcase_add_test(tc, set_tag_refuses_line_breaks_quotes_and_non_ascii);
    tcase_add_test(tc, fingers_without_fingers);
    tcase_add_test(tc, fmf_finger_data_and_tare);
    suite_add_tcase(s, tc);
    return s;
}
