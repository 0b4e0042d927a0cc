/* SPDX-License-Identifier: BSD-3-Clause */
/* The streaming request deframer (wsg_bin_frame.h): preamble search, header,
 * payload, checksum; one byte at a time, so any split of the stream works. */
#include <string.h>

#include "wsg_bin_frame.h"

void wsg_bin_framer_init(wsg_bin_framer_t *f, bool check_crc)
{
    memset(f, 0, sizeof(*f));
    f->state = WSG_BIN_SYNC;
    f->check_crc = check_crc;
}

void wsg_bin_framer_set_crc_check(wsg_bin_framer_t *f, bool check_crc)
{
    f->check_crc = check_crc;
}

static void restart_sync(wsg_bin_framer_t *f)
{
    f->state = WSG_BIN_SYNC;
    f->preamble_run = 0;
    f->frame_bytes = 0;
}

/* Counts 0xAA runs; a byte other than 0xAA after a run of at least three is
 * the ID and starts a frame, anywhere else it and the run are noise. */
static void sync_byte(wsg_bin_framer_t *f, uint8_t byte)
{
    if (byte == WSG_BIN_PREAMBLE_BYTE) {
        if (f->preamble_run < WSG_BIN_PREAMBLE_LEN) {
            f->preamble_run++;
        } else {
            f->skipped++; /* a longer run: only three belong to the frame */
        }
        return;
    }
    if (f->preamble_run < WSG_BIN_PREAMBLE_LEN) {
        f->skipped += f->preamble_run + 1u;
        f->preamble_run = 0;
        return;
    }
    f->id = byte;
    f->crc = wsg_bin_crc_update(WSG_BIN_CRC_AFTER_PREAMBLE, &byte, 1);
    f->frame_bytes = WSG_BIN_PREAMBLE_LEN + 1u;
    f->state = WSG_BIN_LEN_LO;
}

static void header_or_payload_byte(wsg_bin_framer_t *f, uint8_t byte)
{
    switch (f->state) {
    case WSG_BIN_LEN_LO:
        f->length = byte;
        f->state = WSG_BIN_LEN_HI;
        break;
    case WSG_BIN_LEN_HI:
        f->length = (uint16_t)(f->length | (uint16_t)byte << 8);
        f->received = 0;
        f->state = f->length > 0 ? WSG_BIN_PAYLOAD : WSG_BIN_CRC_LO;
        break;
    case WSG_BIN_PAYLOAD:
        if (f->received < WSG_BIN_PAYLOAD_MAX) {
            f->payload[f->received] = byte;
        }
        f->received++;
        if (f->received == f->length) {
            f->state = WSG_BIN_CRC_LO;
        }
        break;
    default:
        break;
    }
}

static void report_frame(wsg_bin_framer_t *f, uint8_t crc_hi, wsg_bin_frame_t *frame)
{
    frame->id = f->id;
    frame->length = f->length;
    frame->too_long = f->length > WSG_BIN_PAYLOAD_MAX;
    frame->payload = frame->too_long ? NULL : f->payload;
    frame->crc = (uint16_t)(f->crc_lo | (uint16_t)crc_hi << 8);
    /* f->crc ran over the CRC bytes too: an intact frame ends at 0 (§2.3) */
    frame->crc_ok = !f->check_crc || f->crc == 0;
    restart_sync(f);
}

bool wsg_bin_framer_push(wsg_bin_framer_t *f, uint8_t byte, wsg_bin_frame_t *frame)
{
    if (f->state == WSG_BIN_SYNC) {
        sync_byte(f, byte);
        return false;
    }
    f->crc = wsg_bin_crc_update(f->crc, &byte, 1);
    f->frame_bytes++;
    if (f->state == WSG_BIN_CRC_LO) {
        f->crc_lo = byte;
        f->state = WSG_BIN_CRC_HI;
        return false;
    }
    if (f->state == WSG_BIN_CRC_HI) {
        report_frame(f, byte, frame);
        return true;
    }
    header_or_payload_byte(f, byte);
    return false;
}

bool wsg_bin_framer_feed(wsg_bin_framer_t *f, const uint8_t **bytes, size_t *len,
                         wsg_bin_frame_t *frame)
{
    while (*len > 0) {
        uint8_t byte = **bytes;
        (*bytes)++;
        (*len)--;
        if (wsg_bin_framer_push(f, byte, frame)) {
            return true;
        }
    }
    return false;
}

void wsg_bin_framer_discard(wsg_bin_framer_t *f)
{
    f->skipped += f->state == WSG_BIN_SYNC ? f->preamble_run : f->frame_bytes;
    restart_sync(f);
}

uint32_t wsg_bin_framer_skipped(const wsg_bin_framer_t *f)
{
    return f->skipped;
}
