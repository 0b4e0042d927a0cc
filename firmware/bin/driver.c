/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary protocol driver (wsg_bin.h): frames in, one reply frame per
 * write out; the checks every request passes in the documented order, the
 * command table, pending and final replies. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "bin/bin_internal.h"

typedef struct {
    uint8_t id;
    const char *name; /* as tools/wsgbin names it */
    bin_handler_t handler;
} bin_command_t;

static const bin_command_t commands[] = {
    {0x06, "loop", wsg_bin_loop},
    {0x07, "disconnect", wsg_bin_disconnect},
    {0x20, "homing", wsg_bin_homing},
    {0x21, "preposition", wsg_bin_preposition},
    {0x22, "stop", wsg_bin_stop},
    {0x23, "fast-stop", wsg_bin_fast_stop},
    {0x24, "ack", wsg_bin_ack},
    {0x25, "grasp", wsg_bin_grasp},
    {0x26, "release", wsg_bin_release},
    {0x30, "set-acc", wsg_bin_set_acc},
    {0x31, "get-acc", wsg_bin_get_acc},
    {0x32, "set-force", wsg_bin_set_force},
    {0x33, "get-force-limit", wsg_bin_get_force_limit},
    {0x34, "set-soft-limits", wsg_bin_set_soft_limits},
    {0x35, "get-soft-limits", wsg_bin_get_soft_limits},
    {0x36, "clear-soft-limits", wsg_bin_clear_soft_limits},
    {0x37, "overdrive", wsg_bin_overdrive},
    {0x38, "tare", wsg_bin_tare},
    {0x40, "get-state", wsg_bin_get_state},
    {0x41, "get-grasp-state", wsg_bin_get_grasp_state},
    {0x42, "get-stats", wsg_bin_get_stats},
    {0x43, "get-width", wsg_bin_get_width},
    {0x44, "get-speed", wsg_bin_get_speed},
    {0x45, "get-force", wsg_bin_get_force},
    {0x46, "get-temp", wsg_bin_get_temp},
    {0x50, "system-info", wsg_bin_system_info},
    {0x51, "set-tag", wsg_bin_set_tag},
    {0x52, "get-tag", wsg_bin_get_tag},
    {0x53, "get-limits", wsg_bin_get_limits},
    {0x60, "finger1-info", wsg_bin_finger_info},
    {0x61, "finger1-flags", wsg_bin_finger_flags},
    {0x62, "finger1-power", wsg_bin_finger_power},
    {0x63, "finger1-data", wsg_bin_finger_data},
    {0x70, "finger2-info", wsg_bin_finger_info},
    {0x71, "finger2-flags", wsg_bin_finger_flags},
    {0x72, "finger2-power", wsg_bin_finger_power},
    {0x73, "finger2-data", wsg_bin_finger_data},
};

static const bin_command_t *find_command(uint8_t id)
{
    for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++) {
        if (commands[i].id == id) {
            return &commands[i];
        }
    }
    return NULL;
}

const char *wsg_bin_command_name(uint8_t id)
{
    const bin_command_t *cmd = find_command(id);
    return cmd != NULL ? cmd->name : NULL;
}

void wsg_bin_send(bin_conn_t *b, uint8_t id, wsg_status_t status, const uint8_t *values, size_t len,
                  wsg_msg_kind_t kind)
{
    uint8_t frame[WSG_BIN_REPLY_MAX];
    size_t n = wsg_bin_encode_reply(frame, sizeof(frame), id, (uint16_t)status, values, len);
    if (n == 0) {
        n = wsg_bin_encode_reply(frame, sizeof(frame), id, E_OVERRUN, NULL, 0);
    }
    wsg_conn_write(b->conn, (const char *)frame, n, kind);
}

wsg_status_t wsg_bin_reply_values(bin_req_t *req, const uint8_t *values, size_t len)
{
    wsg_bin_send(req->bin, req->id, E_SUCCESS, values, len, WSG_MSG_REPLY);
    return BIN_REPLIED;
}

wsg_status_t wsg_bin_reply_f32(bin_req_t *req, float value)
{
    uint8_t v[4];
    wsg_bin_put_f32(v, value);
    return wsg_bin_reply_values(req, v, sizeof(v));
}

wsg_status_t wsg_bin_expect_none(const bin_req_t *req)
{
    return req->length == 0 ? E_SUCCESS : E_NO_PARAM_EXPECTED;
}

wsg_status_t wsg_bin_expect_len(const bin_req_t *req, uint16_t len)
{
    return req->length == len ? E_SUCCESS : E_CMD_FORMAT_ERROR;
}

wsg_status_t wsg_bin_get_finite(const bin_req_t *req, size_t offset, float *out)
{
    *out = wsg_bin_get_f32(req->payload + offset);
    return isfinite(*out) ? E_SUCCESS : E_INVALID_PARAMETER;
}

float wsg_bin_clamp(float value, float low, float high)
{
    return value < low ? low : value > high ? high : value;
}

/* The checks of docs/binary-protocol.md in their order, then the command. */
static wsg_status_t run_frame(bin_conn_t *b, const wsg_bin_frame_t *frame)
{
    if (!frame->crc_ok) {
        return E_CHECKSUM_ERROR;
    }
    if (b->announced) {
        return E_ACCESS_DENIED;
    }
    if (wsg_script_registered(bin_device(b), frame->id)) {
        return frame->too_long ? E_CMD_FORMAT_ERROR : wsg_bin_script_queue(b, frame);
    }
    const bin_command_t *cmd = find_command(frame->id);
    if (cmd == NULL) {
        return E_CMD_UNKNOWN;
    }
    if (frame->too_long) {
        return E_CMD_FORMAT_ERROR;
    }
    bin_req_t req = {b, bin_device(b), frame->id, frame->payload, frame->length};
    wsg_device_sense(req.dev);
    return cmd->handler(&req);
}

/* The request as it arrived, for the observers (trace, record): the framer
 * keeps only the payload, so the frame is built again with its own CRC
 * bytes. */
static void note_request(bin_conn_t *b, const wsg_bin_frame_t *frame)
{
    if (b->conn->dev->conn_observer == NULL) {
        wsg_conn_count_input(b->conn);
        return;
    }
    uint8_t raw[WSG_BIN_HEADER_LEN + WSG_BIN_PAYLOAD_MAX + WSG_BIN_CRC_LEN];
    size_t n = wsg_bin_encode_frame(raw, sizeof(raw), frame->id, frame->payload,
                                    frame->too_long ? 0 : frame->length);
    wsg_bin_put_u16(raw + 4, frame->length); /* as declared, also when too long */
    wsg_bin_put_u16(raw + n - WSG_BIN_CRC_LEN, frame->crc);
    wsg_conn_note_input(b->conn, (const char *)raw, n);
}

static void handle_frame(bin_conn_t *b, const wsg_bin_frame_t *frame)
{
    note_request(b, frame);
    wsg_bin_script_note_host(b);
    wsg_status_t status = run_frame(b, frame);
    if (status == BIN_QUEUED) {
        return; /* the script answers, with a status of its own */
    }
    if (status == BIN_REPLIED) {
        wsg_device_note_result(bin_device(b), E_SUCCESS);
        return;
    }
    wsg_device_note_result(bin_device(b), status == E_CMD_PENDING ? E_SUCCESS : status);
    wsg_bin_send(b, frame->id, status, NULL, 0, WSG_MSG_REPLY);
}

static void bin_open(wsg_conn_t *c)
{
    bin_conn_t *b = bin_of(c);
    memset(b, 0, sizeof(*b));
    b->conn = conn_of(c);
    wsg_bin_framer_init(&b->framer, !b->conn->dev->cfg.bin_crc_unchecked);
    b->timer.fire = wsg_bin_updates_fire;
}

static void bin_input(wsg_conn_t *c, const uint8_t *bytes, size_t len)
{
    bin_conn_t *b = bin_of(c);
    wsg_bin_frame_t frame;
    /* the device setting may change while the connection is open */
    wsg_bin_framer_set_crc_check(&b->framer, !b->conn->dev->cfg.bin_crc_unchecked);
    while (b->conn->open && wsg_bin_framer_feed(&b->framer, &bytes, &len, &frame)) {
        handle_frame(b, &frame);
    }
}

/* Each datagram is framed on its own. */
static void bin_end_datagram(wsg_conn_t *c)
{
    wsg_bin_framer_discard(&bin_of(c)->framer);
}

/* The final frame of a long command, with the ID that started it. */
static void bin_done(wsg_conn_t *c, wsg_op_t op, wsg_status_t status)
{
    (void)op;
    bin_conn_t *b = bin_of(c);
    wsg_device_note_result(bin_device(b), status);
    wsg_bin_send(b, b->pending_id, status, NULL, 0, WSG_MSG_REPLY);
}

static bool bin_busy(const wsg_conn_t *c)
{
    return wsg_bin_updates_any(bin_of_const(c));
}

static void bin_close(wsg_conn_t *c, wsg_close_reason_t why)
{
    (void)why;
    wsg_bin_updates_stop(bin_of(c));
    wsg_bin_script_drop_conn(bin_of(c));
}

/* Inside a frame, or past the first bytes of a preamble. */
static bool bin_partial(const wsg_conn_t *c)
{
    const wsg_bin_framer_t *f = &bin_of_const(c)->framer;
    return f->state != WSG_BIN_SYNC || f->preamble_run > 0u;
}

/* 0xAA starts the binary preamble and no GCL line. */
static bool bin_detect(uint8_t first_byte)
{
    return first_byte == 0xAAu;
}

const wsg_proto_driver_t wsg_bin_driver = {
    .name = "binary",
    .detect = bin_detect,
    .open = bin_open,
    .input = bin_input,
    .end_datagram = bin_end_datagram,
    .done = bin_done,
    .busy = bin_busy,
    .close = bin_close,
    .partial = bin_partial,
};
