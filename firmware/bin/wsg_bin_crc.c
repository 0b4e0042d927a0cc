/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary protocol's CRC-16, implemented literally as spec §2.3 describes:
 * the MSB-first lookup table of generator 0x1021, used with the reflected
 * (LSB-first) update rule, initial value 0xFFFF, no final XOR. */
#include "wsg_bin_frame.h"

/* One MSB-first shift/xor step of generator 0x1021 on a 16-bit register. */
#define CRC_STEP(v) (((((v) << 1) ^ (((v)&0x8000u) ? 0x1021u : 0u))) & 0xFFFFu)
/* Table entry of byte value i, taken as (i << 8) through eight steps. */
#define CRC_BYTE(v)                                                                                \
    CRC_STEP(CRC_STEP(CRC_STEP(CRC_STEP(CRC_STEP(CRC_STEP(CRC_STEP(CRC_STEP(v))))))))

/* The table is linear over GF(2) (its register starts at 0), so each entry is
 * the XOR of the entries of its set bits: eight computed constants build all
 * 256 entries at compile time. */
enum {
    CRC_BIT0 = CRC_BYTE(0x0100u),
    CRC_BIT1 = CRC_BYTE(0x0200u),
    CRC_BIT2 = CRC_BYTE(0x0400u),
    CRC_BIT3 = CRC_BYTE(0x0800u),
    CRC_BIT4 = CRC_BYTE(0x1000u),
    CRC_BIT5 = CRC_BYTE(0x2000u),
    CRC_BIT6 = CRC_BYTE(0x4000u),
    CRC_BIT7 = CRC_BYTE(0x8000u)
};

#define CRC_TERM(i, bit) (((i) & (1u << (bit))) ? (unsigned)CRC_BIT##bit : 0u)
#define E(i)                                                                                       \
    (uint16_t)(CRC_TERM(i, 0) ^ CRC_TERM(i, 1) ^ CRC_TERM(i, 2) ^ CRC_TERM(i, 3) ^                 \
               CRC_TERM(i, 4) ^ CRC_TERM(i, 5) ^ CRC_TERM(i, 6) ^ CRC_TERM(i, 7))
#define ROW(r)                                                                                     \
    E((r)*16u + 0u), E((r)*16u + 1u), E((r)*16u + 2u), E((r)*16u + 3u), E((r)*16u + 4u),           \
        E((r)*16u + 5u), E((r)*16u + 6u), E((r)*16u + 7u), E((r)*16u + 8u), E((r)*16u + 9u),       \
        E((r)*16u + 10u), E((r)*16u + 11u), E((r)*16u + 12u), E((r)*16u + 13u), E((r)*16u + 14u),  \
        E((r)*16u + 15u)

static const uint16_t crc_table[256] = {ROW(0u),  ROW(1u),  ROW(2u),  ROW(3u), ROW(4u),  ROW(5u),
                                        ROW(6u),  ROW(7u),  ROW(8u),  ROW(9u), ROW(10u), ROW(11u),
                                        ROW(12u), ROW(13u), ROW(14u), ROW(15u)};

uint16_t wsg_bin_crc_table_entry(uint8_t index)
{
    return crc_table[index];
}

uint16_t wsg_bin_crc_update(uint16_t crc, const uint8_t *bytes, size_t len)
{
    for (size_t i = 0; i < len; i++) {
        crc = (uint16_t)(crc_table[(crc ^ bytes[i]) & 0xFFu] ^ (crc >> 8));
    }
    return crc;
}

uint16_t wsg_bin_crc(const uint8_t *bytes, size_t len)
{
    return wsg_bin_crc_update(WSG_BIN_CRC_INIT, bytes, len);
}
