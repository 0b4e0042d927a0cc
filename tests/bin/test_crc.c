/* SPDX-License-Identifier: BSD-3-Clause */
/* The CRC of spec §2.3 against the published frames. */
#include "hexbytes.h"
#include "suites.h"
#include "vectors.h"
#include "wsg_bin_frame.h"

/* The table entry computed bit by bit: i << 8 through eight MSB-first steps. */
static uint16_t msb_first_entry(unsigned i)
{
    uint16_t reg = (uint16_t)(i << 8);
    for (int step = 0; step < 8; step++) {
        reg = (uint16_t)((reg & 0x8000u) ? (reg << 1) ^ 0x1021u : (unsigned)reg << 1);
    }
    return reg;
}

START_TEST(table_is_the_msb_first_table_of_0x1021)
{
    ck_assert_uint_eq(wsg_bin_crc_table_entry(0), 0x0000);
    ck_assert_uint_eq(wsg_bin_crc_table_entry(1), 0x1021);
    ck_assert_uint_eq(wsg_bin_crc_table_entry(255), 0x1EF0);
    for (unsigned i = 0; i < 256; i++) {
        ck_assert_msg(wsg_bin_crc_table_entry((uint8_t)i) == msb_first_entry(i),
                      "entry %u: 0x%04X, expected 0x%04X", i, wsg_bin_crc_table_entry((uint8_t)i),
                      msb_first_entry(i));
    }
}
END_TEST

START_TEST(crc_after_the_preamble_is_0x50f5)
{
    const uint8_t preamble[] = {0xAA, 0xAA, 0xAA};
    ck_assert_uint_eq(wsg_bin_crc(preamble, sizeof(preamble)), 0x50F5);
    ck_assert_uint_eq(wsg_bin_crc(preamble, sizeof(preamble)), WSG_BIN_CRC_AFTER_PREAMBLE);
}
END_TEST

START_TEST(manual_homing_and_unknown_frames)
{
    uint8_t frame[16];
    size_t n = hex_bytes("AA AA AA 20 02 00 00 00 B3 FD", frame, sizeof(frame));
    ck_assert_uint_eq(wsg_bin_crc(frame, n - 2), 0xFDB3);
    n = hex_bytes("AA AA AA 90 02 00 0E 00 FD 02", frame, sizeof(frame));
    ck_assert_uint_eq(wsg_bin_crc(frame, n - 2), 0x02FD);
}
END_TEST

/* Every vector: the CRC of the covered bytes is the trailer (low byte first),
 * and the receiver's whole-frame check gives 0. */
START_TEST(every_spec_vector)
{
    const bin_vector_t *v = &bin_vectors[_i];
    uint8_t frame[64];
    size_t n = hex_bytes(v->hex, frame, sizeof(frame));
    uint16_t trailer = (uint16_t)(frame[n - 2] | frame[n - 1] << 8);
    ck_assert_msg(wsg_bin_crc(frame, n - 2) == trailer, "%s: CRC 0x%04X, frame says 0x%04X",
                  v->what, wsg_bin_crc(frame, n - 2), trailer);
    ck_assert_msg(wsg_bin_crc(frame, n) == 0, "%s: whole-frame check 0x%04X", v->what,
                  wsg_bin_crc(frame, n));
}
END_TEST

START_TEST(update_continues_across_chunks)
{
    uint8_t frame[64];
    size_t n =
        hex_bytes("AA AA AA 21 09 00 00 00 00 48 42 00 00 C8 42 47 4C", frame, sizeof(frame));
    for (size_t split = 0; split <= n; split++) {
        uint16_t crc = wsg_bin_crc_update(WSG_BIN_CRC_INIT, frame, split);
        crc = wsg_bin_crc_update(crc, frame + split, n - split);
        ck_assert_uint_eq(crc, 0);
    }
    /* clients seed with 0x50F5 after syncing and run from the ID on */
    ck_assert_uint_eq(wsg_bin_crc_update(WSG_BIN_CRC_AFTER_PREAMBLE, frame + 3, n - 3), 0);
}
END_TEST

/* The table/update mismatch: none of CRC-16/CCITT-FALSE (0x29B1), KERMIT
 * (0x2189) or MCRF4XX (0x6F91, the reflected form with init 0xFFFF) for the
 * standard check string. */
START_TEST(is_not_a_catalogued_crc16)
{
    const uint8_t check[] = "123456789";
    uint16_t crc = wsg_bin_crc(check, 9);
    ck_assert_uint_ne(crc, 0x29B1);
    ck_assert_uint_ne(crc, 0x2189);
    ck_assert_uint_ne(crc, 0x6F91);
}
END_TEST

START_TEST(empty_input_leaves_the_register)
{
    ck_assert_uint_eq(wsg_bin_crc(NULL, 0), WSG_BIN_CRC_INIT);
    ck_assert_uint_eq(wsg_bin_crc_update(0x1234, NULL, 0), 0x1234);
}
END_TEST

Suite *bin_crc_suite(void)
{
    Suite *s = suite_create("bin_crc");
    TCase *tc = tcase_create("crc");
    tcase_add_test(tc, table_is_the_msb_first_table_of_0x1021);
    tcase_add_test(tc, crc_after_the_preamble_is_0x50f5);
    tcase_add_test(tc, manual_homing_and_unknown_frames);
    tcase_add_loop_test(tc, every_spec_vector, 0, (int)bin_vector_count);
    tcase_add_test(tc, update_continues_across_chunks);
    tcase_add_test(tc, is_not_a_catalogued_crc16);
    tcase_add_test(tc, empty_input_leaves_the_register);
    suite_add_tcase(s, tc);
    return s;
}
