/* SPDX-License-Identifier: BSD-3-Clause */
/* Frames of the WSG binary command protocol: the checksum, a streaming request
 * framer, the reply encoder and little-endian field helpers.
 * (docs/binary-protocol.md; spec: wsg-binary-protocol.md §2)
 *
 * A frame is  AA AA AA | id | length (u16 LE) | payload | CRC (u16 LE),
 * the CRC covering everything before it. Portable C11: no heap, no OS, no
 * dependency on the device core; all state lives in the caller's objects. */
#ifndef WSG_BIN_FRAME_H
#define WSG_BIN_FRAME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define WSG_BIN_PREAMBLE_BYTE 0xAAu
#define WSG_BIN_PREAMBLE_LEN 3u
#define WSG_BIN_HEADER_LEN 6u /* preamble, id, length */
#define WSG_BIN_CRC_LEN 2u
#define WSG_BIN_STATUS_LEN 2u /* every reply payload starts with the status */

/* The longest request payload any command takes: 0x06 Loop echoes at most 256
 * bytes (manual §3.1.1); the next longest are the device tag 0x51 (64) and the
 * UMI script's 0xB1 (25). A longer request is consumed and reported too long. */
#define WSG_BIN_PAYLOAD_MAX 256u
/* The longest reply: the Loop echo behind its status. */
#define WSG_BIN_REPLY_MAX                                                                          \
    (WSG_BIN_HEADER_LEN + WSG_BIN_STATUS_LEN + WSG_BIN_PAYLOAD_MAX + WSG_BIN_CRC_LEN)
/* Where a reply's values start: a driver may build them there in place. */
#define WSG_BIN_VALUES_OFFSET (WSG_BIN_HEADER_LEN + WSG_BIN_STATUS_LEN)

#define WSG_BIN_CRC_INIT 0xFFFFu
/* The CRC after the three preamble bytes (every frame starts from here). */
#define WSG_BIN_CRC_AFTER_PREAMBLE 0x50F5u

/* The protocol's CRC-16 (spec §2.3): the MSB-first table of generator 0x1021
 * driven by the reflected update rule crc = T[(crc ^ b) & 0xFF] ^ (crc >> 8).
 * No catalogued variant matches it. Continue from `crc` over `len` bytes. */
uint16_t wsg_bin_crc_update(uint16_t crc, const uint8_t *bytes, size_t len);
/* The CRC of `len` bytes from WSG_BIN_CRC_INIT. Over a whole frame including
 * its two CRC bytes it gives 0 when the frame is intact. */
uint16_t wsg_bin_crc(const uint8_t *bytes, size_t len);
/* One entry of the table (exposed for the tests). */
uint16_t wsg_bin_crc_table_entry(uint8_t index);

/* One complete request as the framer saw it. */
typedef struct {
    uint8_t id;
    uint16_t length;        /* the declared payload length */
    const uint8_t *payload; /* `length` bytes; NULL when too_long. Valid until the framer
                               receives its next byte. */
    uint16_t crc;           /* the two checksum bytes as received */
    bool crc_ok;            /* the checksum matched, or checking is off */
    bool too_long;          /* length > WSG_BIN_PAYLOAD_MAX: payload consumed, not kept */
} wsg_bin_frame_t;

typedef enum {
    WSG_BIN_SYNC, /* looking for the preamble; the byte ending it is the ID */
    WSG_BIN_LEN_LO,
    WSG_BIN_LEN_HI,
    WSG_BIN_PAYLOAD,
    WSG_BIN_CRC_LO,
    WSG_BIN_CRC_HI
} wsg_bin_framer_state_t;

/* A streaming request deframer, one per connection (or per datagram source).
 * Bytes outside frames are skipped; a run of three or more consecutive 0xAA
 * bytes is a preamble and the first byte after the run that is not 0xAA is
 * the ID (so no command may use ID 0xAA; none does). Every frame is consumed
 * in full as its length field declares, bad CRC or too long alike, so sync is
 * kept; there is no timeout (the codec has no clock). */
typedef struct {
    wsg_bin_framer_state_t state;
    bool check_crc;
    uint8_t preamble_run; /* consecutive 0xAA seen while syncing, up to 3 */
    uint8_t id;
    uint8_t crc_lo;
    uint16_t length;
    uint16_t received;    /* payload bytes so far */
    uint16_t crc;         /* running over the frame */
    uint32_t frame_bytes; /* bytes of the frame in progress, preamble included */
    uint32_t skipped;     /* bytes that belonged to no frame */
    uint8_t payload[WSG_BIN_PAYLOAD_MAX];
} wsg_bin_framer_t;

void wsg_bin_framer_init(wsg_bin_framer_t *f, bool check_crc);
/* Checking off: the two checksum bytes are still read, and ignored. */
void wsg_bin_framer_set_crc_check(wsg_bin_framer_t *f, bool check_crc);
/* One byte in; true when it completed a frame, which is then in *frame. */
bool wsg_bin_framer_push(wsg_bin_framer_t *f, uint8_t byte, wsg_bin_frame_t *frame);
/* Consumes bytes from *bytes (*len of them) up to the end of the next complete frame and
 * advances them. Returns true with *frame set when a frame completed, false once
 * every byte is used up without one:
 *     while (wsg_bin_framer_feed(&f, &p, &n, &frame)) handle(&frame); */
bool wsg_bin_framer_feed(wsg_bin_framer_t *f, const uint8_t **bytes, size_t *len,
                         wsg_bin_frame_t *frame);
/* Drops a frame in progress (e.g. at the end of a datagram); its bytes count
 * as skipped. Keeps the CRC setting. */
void wsg_bin_framer_discard(wsg_bin_framer_t *f);
/* Bytes skipped since init: noise, false preambles, dropped partial frames. */
uint32_t wsg_bin_framer_skipped(const wsg_bin_framer_t *f);

/* Writes a whole frame (preamble, id, length, payload, valid CRC) into out.
 * Returns its size, or 0 when it does not fit into cap (nothing useful written). */
size_t wsg_bin_encode_frame(uint8_t *out, size_t cap, uint8_t id, const uint8_t *payload,
                            size_t payload_len);
/* Writes a reply frame: status, then values (which may already sit at
 * out + WSG_BIN_VALUES_OFFSET). Returns its size, or 0 when it does not fit. */
size_t wsg_bin_encode_reply(uint8_t *out, size_t cap, uint8_t id, uint16_t status,
                            const uint8_t *values, size_t values_len);

/* Little-endian fields; floats are IEEE-754 binary32. No alignment needed. */
uint16_t wsg_bin_get_u16(const uint8_t *p);
uint32_t wsg_bin_get_u32(const uint8_t *p);
float wsg_bin_get_f32(const uint8_t *p);
void wsg_bin_put_u16(uint8_t *p, uint16_t value);
void wsg_bin_put_u32(uint8_t *p, uint32_t value);
void wsg_bin_put_f32(uint8_t *p, float value);

#endif
