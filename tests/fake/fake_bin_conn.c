/* SPDX-License-Identifier: BSD-3-Clause */
#include "fake_bin_conn.h"

#include <check.h>
#include <string.h>

#include "bin/wsg_bin_frame.h"
#include "wsg/wsg_bin.h"

bin_client_t bc_main;
bin_client_t bc_other;

static void write_frame(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    bin_client_t *c = ctx;
    const uint8_t *b = (const uint8_t *)bytes;
    if (c->count == BC_FRAMES_MAX || len < WSG_BIN_HEADER_LEN + WSG_BIN_STATUS_LEN + 2 ||
        b[0] != 0xAA || b[1] != 0xAA || b[2] != 0xAA || wsg_bin_crc(b, len) != 0 ||
        wsg_bin_get_u16(b + 4) + WSG_BIN_HEADER_LEN + WSG_BIN_CRC_LEN != len) {
        c->bad_frame = true;
        return;
    }
    bc_frame_t *f = &c->frames[c->count++];
    f->id = b[3];
    f->status = wsg_bin_get_u16(b + WSG_BIN_HEADER_LEN);
    f->values_len = len - WSG_BIN_VALUES_OFFSET - WSG_BIN_CRC_LEN;
    memcpy(f->values, b + WSG_BIN_VALUES_OFFSET, f->values_len);
    f->kind = kind;
    f->at_us = h_now_us;
}

static const wsg_conn_io_t capture_io = {.write = write_frame};

void bc_open(bin_client_t *c, wsg_transport_t transport, const wsg_proto_driver_t *drv)
{
    memset(c, 0, sizeof(*c));
    wsg_conn_open(&c->conn, &h_dev, drv, transport, &capture_io, c);
}

void bc_send_crc(bin_client_t *c, uint8_t id, const void *payload, size_t len, uint16_t crc)
{
    uint8_t frame[WSG_BIN_HEADER_LEN + 512 + WSG_BIN_CRC_LEN];
    ck_assert_uint_le(len, 512);
    size_t n = wsg_bin_encode_frame(frame, sizeof(frame), id, payload, len);
    wsg_bin_put_u16(frame + n - 2, crc);
    wsg_conn_input(&c->conn, frame, n);
}

void bc_send(bin_client_t *c, uint8_t id, const void *payload, size_t len)
{
    uint8_t frame[WSG_BIN_HEADER_LEN + 512 + WSG_BIN_CRC_LEN];
    ck_assert_uint_le(len, 512);
    size_t n = wsg_bin_encode_frame(frame, sizeof(frame), id, payload, len);
    wsg_conn_input(&c->conn, frame, n);
}

const bc_frame_t *bc_next(bin_client_t *c)
{
    return c->read < c->count ? &c->frames[c->read++] : NULL;
}

size_t bc_unread(const bin_client_t *c)
{
    return c->count - c->read;
}

static const bc_frame_t *bc_await(bin_client_t *c, uint32_t timeout_ms)
{
    for (uint32_t i = 0; i <= timeout_ms && bc_unread(c) == 0; i++) {
        advance_ms(1);
    }
    return bc_next(c);
}

static const bc_frame_t *check_frame(const bc_frame_t *f, uint8_t id, uint16_t status)
{
    ck_assert_msg(f != NULL, "no frame, expected 0x%02x status %u", id, status);
    ck_assert_msg(f->id == id && f->status == status,
                  "got 0x%02x status %u, expected 0x%02x status %u", f->id, f->status, id, status);
    return f;
}

const bc_frame_t *bc_expect(bin_client_t *c, uint8_t id, uint16_t status)
{
    return check_frame(bc_next(c), id, status);
}

const bc_frame_t *bc_await_expect(bin_client_t *c, uint8_t id, uint16_t status, uint32_t timeout_ms)
{
    return check_frame(bc_await(c, timeout_ms), id, status);
}

void bc_expect_none(bin_client_t *c)
{
    const bc_frame_t *f = bc_next(c);
    ck_assert_msg(f == NULL, "unexpected frame 0x%02x status %u", f ? f->id : 0, f ? f->status : 0);
}

float bc_f32(const bc_frame_t *f, size_t offset)
{
    ck_assert_uint_ge(f->values_len, offset + 4);
    return wsg_bin_get_f32(f->values + offset);
}

void bc_move(bin_client_t *c, uint8_t flags, float width, float speed)
{
    uint8_t p[9];
    p[0] = flags;
    wsg_bin_put_f32(p + 1, width);
    wsg_bin_put_f32(p + 5, speed);
    bc_send(c, 0x21, p, sizeof(p));
}

void bc_query(bin_client_t *c, uint8_t id, uint8_t flags, uint16_t period_ms)
{
    uint8_t p[3];
    p[0] = flags;
    wsg_bin_put_u16(p + 1, period_ms);
    bc_send(c, id, p, sizeof(p));
}

void bc_setup(void)
{
    h_setup();
    memset(&bc_other, 0, sizeof(bc_other));
    bc_open(&bc_main, WSG_TRANSPORT_STREAM, &wsg_bin_driver);
}

void bc_setup_homed(void)
{
    bc_setup();
    const uint8_t dir = 0;
    bc_send(&bc_main, 0x20, &dir, 1);
    bc_expect(&bc_main, 0x20, E_CMD_PENDING);
    bc_await_expect(&bc_main, 0x20, E_SUCCESS, 5000);
    bc_expect_none(&bc_main);
}

void bc_teardown(void)
{
    h_teardown();
    ck_assert_msg(!bc_main.bad_frame && !bc_other.bad_frame, "a write was not one valid frame");
}
