/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary protocol driver (wsg_bin.h): frames in, one reply frame per
 * write out; the checks every request passes in the documented order,
 * pending and final replies. The command table is commands.c, the
 * handlers' replies reply.c. */
#include <stddef.h>
#include <string.h>

#include "bin/bin_internal.h"

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
    const bin_command_t *cmd = wsg_bin_find_command(frame->id);
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
    if (b->conn->dev->observers.conn == NULL) {
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

/* The kind of a request for the command processor's service time
 * (docs/timing.md). */
static wsg_request_kind_t request_kind(const bin_conn_t *b, uint8_t id)
{
    if (wsg_script_registered(bin_device(b), id)) {
        return WSG_REQ_SCRIPT;
    }
    if (id >= 0x20u && id <= 0x26u) {
        return WSG_REQ_MOTION;
    }
    return id >= 0x40u && id <= 0x5Fu ? WSG_REQ_QUERY : WSG_REQ_SETTING;
}

static size_t bin_input(wsg_conn_t *c, const uint8_t *bytes, size_t len)
{
    bin_conn_t *b = bin_of(c);
    wsg_bin_frame_t frame;
    size_t given = len;
    if (b->conn->request_waits) {
        return 0; /* the rest waits in the port, as in a busy device's receive buffer */
    }
    /* the device setting may change while the connection is open */
    wsg_bin_framer_set_crc_check(&b->framer, !b->conn->dev->cfg.bin_crc_unchecked);
    while (b->conn->open && wsg_bin_framer_feed(&b->framer, &bytes, &len, &frame)) {
        if (wsg_conn_timed(b->conn)) {
            /* held until served: the framer keeps its payload until the next feed */
            b->held = frame;
            wsg_proc_submit(b->conn, request_kind(b, frame.id));
            break;
        }
        handle_frame(b, &frame);
    }
    return given - len;
}

static void bin_serve(wsg_conn_t *c)
{
    bin_conn_t *b = bin_of(c);
    handle_frame(b, &b->held);
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
    .serve = bin_serve,
};
