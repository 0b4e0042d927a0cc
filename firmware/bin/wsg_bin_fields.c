/* SPDX-License-Identifier: BSD-3-Clause */
/* Little-endian field access for frame payloads, alignment- and host-order-
 * independent; floats go through memcpy to a uint32_t (no type punning). */
#include <string.h>

#include "wsg_bin_frame.h"

_Static_assert(sizeof(float) == sizeof(uint32_t), "the protocol's floats are binary32");

uint16_t wsg_bin_get_u16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (uint16_t)p[1] << 8);
}

uint32_t wsg_bin_get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

float wsg_bin_get_f32(const uint8_t *p)
{
    uint32_t bits = wsg_bin_get_u32(p);
    float value;
    memcpy(&value, &bits, sizeof(value));
    return value;
}

void wsg_bin_put_u16(uint8_t *p, uint16_t value)
{
    p[0] = (uint8_t)(value & 0xFFu);
    p[1] = (uint8_t)(value >> 8);
}

void wsg_bin_put_u32(uint8_t *p, uint32_t value)
{
    for (unsigned i = 0; i < 4; i++) {
        p[i] = (uint8_t)(value >> (8 * i));
    }
}

void wsg_bin_put_f32(uint8_t *p, float value)
{
    uint32_t bits;
    memcpy(&bits, &value, sizeof(bits));
    wsg_bin_put_u32(p, bits);
}
