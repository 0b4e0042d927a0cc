/* SPDX-License-Identifier: BSD-3-Clause */
/* Frame encoding: every frame leaves with a valid CRC, whether or not the
 * device checks the CRCs it receives (spec §2.4). */
#include <string.h>

#include "wsg_bin_frame.h"

/* The payload already sits at out + WSG_BIN_HEADER_LEN: adds header and CRC. */
static size_t finish_frame(uint8_t *out, uint8_t id, size_t payload_len)
{
    for (size_t i = 0; i < WSG_BIN_PREAMBLE_LEN; i++) {
        out[i] = WSG_BIN_PREAMBLE_BYTE;
    }
    out[WSG_BIN_PREAMBLE_LEN] = id;
    wsg_bin_put_u16(out + WSG_BIN_PREAMBLE_LEN + 1, (uint16_t)payload_len);
    size_t covered = WSG_BIN_HEADER_LEN + payload_len;
    wsg_bin_put_u16(out + covered, wsg_bin_crc(out, covered));
    return covered + WSG_BIN_CRC_LEN;
}

static bool frame_fits(size_t cap, size_t payload_len)
{
    return payload_len <= UINT16_MAX && cap >= WSG_BIN_HEADER_LEN + WSG_BIN_CRC_LEN &&
           payload_len <= cap - WSG_BIN_HEADER_LEN - WSG_BIN_CRC_LEN;
}

size_t wsg_bin_encode_frame(uint8_t *out, size_t cap, uint8_t id, const uint8_t *payload,
                            size_t payload_len)
{
    if (!frame_fits(cap, payload_len)) {
        return 0;
    }
    if (payload_len > 0) {
        memmove(out + WSG_BIN_HEADER_LEN, payload, payload_len);
    }
    return finish_frame(out, id, payload_len);
}

size_t wsg_bin_encode_reply(uint8_t *out, size_t cap, uint8_t id, uint16_t status,
                            const uint8_t *values, size_t values_len)
{
    if (values_len > UINT16_MAX - WSG_BIN_STATUS_LEN ||
        !frame_fits(cap, WSG_BIN_STATUS_LEN + values_len)) {
        return 0;
    }
    /* values first: they may overlap out (built in place at VALUES_OFFSET) */
    if (values_len > 0) {
        memmove(out + WSG_BIN_VALUES_OFFSET, values, values_len);
    }
    wsg_bin_put_u16(out + WSG_BIN_HEADER_LEN, status);
    return finish_frame(out, id, WSG_BIN_STATUS_LEN + values_len);
}
