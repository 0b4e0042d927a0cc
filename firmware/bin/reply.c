/* SPDX-License-Identifier: BSD-3-Clause */
/* What every handler uses: reply frames, length checks and argument reads.
 * A leaf of the driver, so the handlers do not depend on the driver that
 * calls them. */
#include <math.h>

#include "bin/bin_internal.h"

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
