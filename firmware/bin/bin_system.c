/* SPDX-License-Identifier: BSD-3-Clause */
/* Connection and system commands: 0x06 loop, 0x07 disconnect, 0x50-0x53. */
#include <string.h>

#include "bin/bin_internal.h"

wsg_status_t wsg_bin_loop(bin_req_t *req)
{
    return wsg_bin_reply_values(req, req->payload, req->length);
}

/* Aborts this connection's motion, ends its updates; afterwards every
 * command is E_ACCESS_DENIED and the close raises no FAST STOP. */
wsg_status_t wsg_bin_disconnect(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    bin_conn_t *b = req->bin;
    if (b->conn->transport != WSG_TRANSPORT_STREAM) {
        return E_NOT_AVAILABLE;
    }
    if (wsg_conn_owns_motion(conn_public(b->conn))) {
        wsg_op_stop(req->dev);
    }
    wsg_bin_updates_stop(b);
    b->announced = true;
    b->conn->close_announced = true;
    return E_SUCCESS;
}

/* "4.0.2" -> 0x4020: one nibble per digit group, at most four. */
static uint16_t firmware_nibbles(const char *version)
{
    uint16_t value = 0;
    unsigned digits = 0;
    for (const char *p = version; *p != '\0' && digits < 4; p++) {
        if (*p >= '0' && *p <= '9') {
            value = (uint16_t)(value | ((unsigned)(*p - '0') & 0xFu) << (12u - 4u * digits));
            digits++;
        }
    }
    return value;
}

/* The 0x50 device type code of a model name (spec §5: 1 WSG 50, 2 WSG 32,
 * 5 WSG 25, 6 WSG 70; 0 unknown). */
static uint8_t device_type(const char *devtype)
{
    static const struct {
        const char *prefix;
        uint8_t code;
    } types[] = {{"WSG 50", 1}, {"WSG 32", 2}, {"WSG 25", 5}, {"WSG 70", 6}};
    for (size_t i = 0; i < sizeof(types) / sizeof(types[0]); i++) {
        if (strncmp(devtype, types[i].prefix, strlen(types[i].prefix)) == 0) {
            return types[i].code;
        }
    }
    return 0;
}

wsg_status_t wsg_bin_system_info(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_config_t *cfg = wsg_device_snapshot(req->dev)->config;
    uint8_t v[8];
    v[0] = device_type(cfg->devtype);
    v[1] = cfg->hw_revision;
    wsg_bin_put_u16(v + 2, firmware_nibbles(cfg->version));
    wsg_bin_put_u32(v + 4, cfg->serial);
    return wsg_bin_reply_values(req, v, sizeof(v));
}

/* Trailing NULs (a fixed-size field) are stripped; the core checks the
 * rest, a NUL inside included. */
wsg_status_t wsg_bin_set_tag(bin_req_t *req)
{
    size_t len = req->length;
    while (len > 0 && req->payload[len - 1] == '\0') {
        len--;
    }
    return wsg_op_set_tag(req->dev, (const char *)req->payload, len);
}

wsg_status_t wsg_bin_get_tag(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    const char *tag = wsg_device_snapshot(req->dev)->config->tag;
    if (tag[0] == '\0') {
        return E_NOT_AVAILABLE;
    }
    return wsg_bin_reply_values(req, (const uint8_t *)tag, strlen(tag));
}

/* The overdrive force field: the nominal maximum on a model without an
 * overdrive mode, never 0. Drake's schunk_driver clamps every force
 * command to this field, and with 0 it never moves the jaws
 * (docs/binary-protocol.md). */
static float overdrive_force(const wsg_config_t *cfg)
{
    return cfg->force_overdrive_n > 0.0f ? cfg->force_overdrive_n : cfg->force_max_n;
}

/* stroke, min/max speed, min/max acceleration, min/nominal/overdrive force */
wsg_status_t wsg_bin_get_limits(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_config_t *cfg = wsg_device_snapshot(req->dev)->config;
    const float limits[8] = {cfg->stroke_mm,       cfg->speed_min_mm_s,  cfg->speed_max_mm_s,
                             cfg->accel_min_mm_s2, cfg->accel_max_mm_s2, cfg->force_min_n,
                             cfg->force_max_n,     overdrive_force(cfg)};
    uint8_t v[32];
    for (unsigned i = 0; i < 8; i++) {
        wsg_bin_put_f32(v + 4 * i, limits[i]);
    }
    return wsg_bin_reply_values(req, v, sizeof(v));
}
