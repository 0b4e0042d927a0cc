/* SPDX-License-Identifier: BSD-3-Clause */
/* The plant protocol's messages (host/physics/plant_wire.c) at the byte
 * offsets docs/physics.md ("Plant protocol") gives, and the replies the
 * device refuses: each a lost plant. */
#include <check.h>
#include <math.h>
#include <string.h>

#include "host_suites.h"
#include "plant_wire.h"

static uint8_t reply[PLANT_WIRE_HEADER + PLANT_WIRE_PAYLOAD_MAX];

/* A reply header of type with status and length. */
static void header(uint8_t type, uint16_t status, uint32_t length)
{
    memcpy(reply, "WSGP", 4);
    reply[4] = 1u;
    reply[5] = type;
    reply[6] = (uint8_t)status;
    reply[7] = (uint8_t)(status >> 8);
    plant_wire_put_u32(reply + 8, length);
}

/* A sample: 40 mm, a pad force of 10 N on both pads, spread evenly. */
static uint8_t *good_sample(void)
{
    uint8_t *s = reply + PLANT_WIRE_HEADER;
    memset(s, 0, PLANT_WIRE_SAMPLE);
    s[0] = 0xE8; /* time: 1000 us */
    s[1] = 0x03;
    plant_wire_put_f32(s + 8, 40.0f);
    plant_wire_put_f32(s + 20, 10.0f);
    for (unsigned f = 0; f < 2u; f++) {
        plant_wire_put_f32(s + 28 + 340 * f, 10.0f);
        for (unsigned c = 0; c < PLANT_PAD_CELLS; c++) {
            plant_wire_put_f32(s + 32 + 340 * f + 4 * c, 10.0f / PLANT_PAD_CELLS);
        }
    }
    return s;
}

static float f32_at(const uint8_t *at)
{
    uint32_t bits =
        (uint32_t)at[0] | (uint32_t)at[1] << 8 | (uint32_t)at[2] << 16 | (uint32_t)at[3] << 24;
    float v;
    memcpy(&v, &bits, sizeof(v));
    return v;
}

START_TEST(a_step_request_is_laid_out_as_documented)
{
    uint8_t payload[PLANT_WIRE_STEP_REQ];
    uint8_t out[PLANT_WIRE_HEADER + PLANT_WIRE_STEP_REQ];
    plant_drive_t drive = {true, 39.5f, -20.0f, 40.0f};
    plant_wire_step_payload(payload, &drive, 1000u);
    ck_assert_uint_eq(plant_wire_request(out, PLANT_MSG_STEP, payload, sizeof(payload)), 32u);
    static const uint8_t head[12] = {'W', 'S', 'G', 'P', 1, 3, 0, 0, 20, 0, 0, 0};
    ck_assert_mem_eq(out, head, sizeof(head));
    static const uint8_t dt_enabled[8] = {0xE8, 0x03, 0, 0, 1, 0, 0, 0};
    ck_assert_mem_eq(out + 12, dt_enabled, sizeof(dt_enabled));
    ck_assert_float_eq(f32_at(out + 20), 39.5f);
    ck_assert_float_eq(f32_at(out + 24), -20.0f);
    ck_assert_float_eq(f32_at(out + 28), 40.0f);
}
END_TEST

START_TEST(a_good_sample_is_read)
{
    plant_wire_header_t h;
    header(PLANT_MSG_STEP, 0u, PLANT_WIRE_SAMPLE);
    ck_assert_ptr_null(plant_wire_header(reply, PLANT_MSG_STEP, &h));
    plant_sample_t s;
    ck_assert_ptr_null(plant_wire_sample(good_sample(), h.length, &s));
    ck_assert_uint_eq(s.time_us, 1000u);
    ck_assert_float_eq(s.width_mm, 40.0f);
    ck_assert_float_eq(s.jaw_force_n, 10.0f);
    ck_assert_float_eq(s.pad[1].force_n, 10.0f);
    ck_assert_float_eq_tol(s.pad[1].cells_n[83], 10.0f / 84.0f, 1e-6f);
}
END_TEST

START_TEST(a_header_that_does_not_fit_its_request_is_refused)
{
    plant_wire_header_t h;
    header(PLANT_MSG_STEP, 0u, PLANT_WIRE_SAMPLE - 1u);
    ck_assert_str_eq(plant_wire_header(reply, PLANT_MSG_STEP, &h), "bad length");
    header(PLANT_MSG_BODY, 0u, PLANT_WIRE_SAMPLE);
    ck_assert_str_eq(plant_wire_header(reply, PLANT_MSG_STEP, &h), "a reply to another request");
    header(PLANT_MSG_STEP, PLANT_ERR_UNSUPPORTED, 0u);
    ck_assert_str_eq(plant_wire_header(reply, PLANT_MSG_STEP, &h), "the plant refused a step");
    header(PLANT_MSG_SET, 9u, 0u);
    ck_assert_str_eq(plant_wire_header(reply, PLANT_MSG_SET, &h), "an unknown status");
    header(PLANT_MSG_SET, PLANT_ERR_FIXED, 0u); /* a refused change: no fault */
    ck_assert_ptr_null(plant_wire_header(reply, PLANT_MSG_SET, &h));
    reply[4] = 2u;
    ck_assert_str_eq(plant_wire_header(reply, PLANT_MSG_SET, &h),
                     "the plant speaks another protocol version");
    reply[0] = 'w';
    ck_assert_str_eq(plant_wire_header(reply, PLANT_MSG_SET, &h),
                     "not a plant protocol reply (bad magic)");
}
END_TEST

START_TEST(a_sample_out_of_range_is_refused)
{
    plant_sample_t s;
    uint8_t *payload = good_sample();
    plant_wire_put_f32(payload + 8, NAN);
    ck_assert_ptr_nonnull(plant_wire_sample(payload, PLANT_WIRE_SAMPLE, &s));
    payload = good_sample();
    plant_wire_put_f32(payload + 12, 2e9f);
    ck_assert_ptr_nonnull(plant_wire_sample(payload, PLANT_WIRE_SAMPLE, &s));
    payload = good_sample();
    plant_wire_put_f32(payload + 368 + 4, -0.5f); /* the right pad's first cell */
    ck_assert_ptr_nonnull(plant_wire_sample(payload, PLANT_WIRE_SAMPLE, &s));
}
END_TEST

START_TEST(a_body_whose_name_is_no_word_is_refused)
{
    plant_body_t b;
    uint8_t *payload = reply + PLANT_WIRE_HEADER;
    memset(payload, 0, PLANT_WIRE_BODY_REPLY);
    memcpy(payload, "box", 4);
    ck_assert_ptr_null(plant_wire_body(payload, PLANT_WIRE_BODY_REPLY, &b));
    ck_assert_str_eq(b.name, "box");
    memcpy(payload, "a \"box\"", 8);
    ck_assert_ptr_nonnull(plant_wire_body(payload, PLANT_WIRE_BODY_REPLY, &b));
    memset(payload, 'x', PLANT_NAME_MAX); /* no NUL: cut, still a word */
    ck_assert_ptr_null(plant_wire_body(payload, PLANT_WIRE_BODY_REPLY, &b));
    ck_assert_uint_eq(strlen(b.name), PLANT_NAME_MAX - 1u);
}
END_TEST

START_TEST(more_contacts_than_asked_for_are_refused)
{
    plant_contact_t c[2];
    unsigned total = 0u;
    uint8_t *payload = reply + PLANT_WIRE_HEADER;
    memset(payload, 0, 8u + 3u * PLANT_WIRE_CONTACT);
    plant_wire_put_u32(payload, 3u);
    plant_wire_put_u32(payload + 4, 3u);
    ck_assert_ptr_nonnull(
        plant_wire_contacts(payload, 8u + 3u * PLANT_WIRE_CONTACT, c, 2u, &total));
    plant_wire_put_u32(payload + 4, 2u);
    plant_wire_put_f64(payload + 8 + 56, 12.5); /* the first contact's normal force */
    ck_assert_ptr_null(plant_wire_contacts(payload, 8u + 2u * PLANT_WIRE_CONTACT, c, 2u, &total));
    ck_assert_uint_eq(total, 3u);
    ck_assert_double_eq(c[0].normal_n, 12.5);
}
END_TEST

Suite *plant_wire_suite(void)
{
    Suite *s = suite_create("plant_wire");
    TCase *tc = tcase_create("messages");
    tcase_add_test(tc, a_step_request_is_laid_out_as_documented);
    tcase_add_test(tc, a_good_sample_is_read);
    tcase_add_test(tc, a_header_that_does_not_fit_its_request_is_refused);
    tcase_add_test(tc, a_sample_out_of_range_is_refused);
    tcase_add_test(tc, a_body_whose_name_is_no_word_is_refused);
    tcase_add_test(tc, more_contacts_than_asked_for_are_refused);
    suite_add_tcase(s, tc);
    return s;
}
