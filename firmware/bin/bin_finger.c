/* SPDX-License-Identifier: BSD-3-Clause */
/* Finger commands, firmware-4 style (docs/binary-protocol.md): 0x6x finger
 * 1, 0x7x finger 2, no index byte. */
#include "bin/bin_internal.h"

#define BIN_FINGER_TYPE_NONE 255u

static const wsg_finger_t *finger(const bin_req_t *req)
{
    unsigned slot = (req->id & 0xF0u) == 0x70u ? 1u : 0u;
    return &wsg_device_snapshot(req->dev)->fingers->slot[slot];
}

wsg_status_t wsg_bin_finger_info(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_finger_t *f = finger(req);
    uint8_t v[3];
    uint16_t size = 0;
    switch (f->type) {
    case FINGER_GENERIC:
        v[0] = 0;
        break;
    case FINGER_FMF:
        v[0] = 1;
        size = 4;
        break;
    case FINGER_DSA:
        v[0] = 2;
        size = 2u * WSG_FINGER_DATA_MAX;
        break;
    case FINGER_NONE:
    default:
        v[0] = BIN_FINGER_TYPE_NONE;
        break;
    }
    wsg_bin_put_u16(v + 1, size);
    return wsg_bin_reply_values(req, v, sizeof(v));
}

wsg_status_t wsg_bin_finger_flags(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    uint8_t v[2];
    wsg_bin_put_u16(v, finger(req)->flags);
    return wsg_bin_reply_values(req, v, sizeof(v));
}

/* The simulated fingers are powered while plugged in: asking for the state
 * they are in succeeds, switching them is not supported. */
wsg_status_t wsg_bin_finger_power(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_len(req, 1);
    if (status != E_SUCCESS) {
        return status;
    }
    bool powered = (finger(req)->flags & (1u << FF_POWER_ON)) != 0;
    return ((req->payload[0] & 1u) != 0) == powered ? E_SUCCESS : E_FEATURE_NOT_SUPPORTED;
}

wsg_status_t wsg_bin_finger_data(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_finger_t *f = finger(req);
    if (!wsg_finger_has_data(f) || (f->type != FINGER_FMF && f->type != FINGER_DSA)) {
        return E_NOT_AVAILABLE;
    }
    if (f->type == FINGER_FMF) {
        return wsg_bin_reply_f32(req, f->data[0]);
    }
    uint8_t v[2u * WSG_FINGER_DATA_MAX];
    for (unsigned i = 0; i < f->data_count && i < WSG_FINGER_DATA_MAX; i++) {
        wsg_bin_put_u16(v + 2 * i, (uint16_t)f->data[i]);
    }
    return wsg_bin_reply_values(req, v, 2u * f->data_count);
}
