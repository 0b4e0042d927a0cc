/* SPDX-License-Identifier: BSD-3-Clause */
/* Motion commands 0x20-0x26 (spec §5): long ones answer E_CMD_PENDING and a
 * final frame with the same ID; widths, speeds and forces are clamped to
 * the device's limits, a target in a soft-limit zone is E_RANGE_ERROR. */
#include "bin/bin_internal.h"

static const wsg_config_t *config(const bin_req_t *req)
{
    return wsg_device_snapshot(req->dev)->config;
}

/* A motion runs: the binary protocol refuses a second one (GCL's MOVE
 * would retarget). A stopped one has ended already. */
static bool motion_running(const bin_req_t *req)
{
    return wsg_device_snapshot(req->dev)->motion != WSG_MOTION_NONE;
}

static wsg_status_t pending(bin_req_t *req, wsg_status_t started)
{
    if (started != E_SUCCESS) {
        return started;
    }
    req->bin->pending_id = req->id;
    return E_CMD_PENDING;
}

static float clamp_speed(const wsg_config_t *cfg, float speed)
{
    return wsg_bin_clamp(speed, cfg->speed_min_mm_s, cfg->speed_max_mm_s);
}

/* Clamped to the stroke; inside a soft-limit zone is a range error. */
static wsg_status_t check_width(const wsg_config_t *cfg, float *width)
{
    *width = wsg_bin_clamp(*width, 0.0f, cfg->stroke_mm);
    if (!wsg_config_target_ok(cfg, *width)) {
        return E_RANGE_ERROR;
    }
    return E_SUCCESS;
}

wsg_status_t wsg_bin_homing(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_len(req, 1);
    if (status != E_SUCCESS) {
        return status;
    }
    if (req->payload[0] > 2) {
        return E_INVALID_PARAMETER;
    }
    if (motion_running(req)) {
        return E_ALREADY_RUNNING;
    }
    static const wsg_home_dir_t dirs[] = {WSG_HOME_DEFAULT, WSG_HOME_POSITIVE, WSG_HOME_NEGATIVE};
    wsg_home_args_t args = {dirs[req->payload[0]]};
    return pending(req, wsg_op_home(req->dev, wsg_conn_owner(conn_public(req->bin->conn)), &args));
}

wsg_status_t wsg_bin_preposition(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_len(req, 9);
    float width = 0.0f;
    float speed = 0.0f;
    if (status == E_SUCCESS) {
        status = wsg_bin_get_finite(req, 1, &width);
    }
    if (status == E_SUCCESS) {
        status = wsg_bin_get_finite(req, 5, &speed);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_snapshot_t *snap = wsg_device_snapshot(req->dev);
    const wsg_config_t *cfg = snap->config;
    uint8_t flags = req->payload[0];
    if (flags & 0x01u) {
        width += snap->position_mm;
    }
    status = check_width(cfg, &width);
    if (status != E_SUCCESS) {
        return status;
    }
    if (motion_running(req)) {
        return E_ALREADY_RUNNING;
    }
    wsg_move_args_t args = {width, clamp_speed(cfg, speed), false, (flags & 0x02u) != 0};
    return pending(req, wsg_op_move(req->dev, wsg_conn_owner(conn_public(req->bin->conn)), &args));
}

/* Grasp and release share the request layout: width, speed. */
static wsg_status_t width_speed(const bin_req_t *req, float *width, float *speed)
{
    wsg_status_t status = wsg_bin_expect_len(req, 8);
    if (status == E_SUCCESS) {
        status = wsg_bin_get_finite(req, 0, width);
    }
    if (status == E_SUCCESS) {
        status = wsg_bin_get_finite(req, 4, speed);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_config_t *cfg = config(req);
    *speed = clamp_speed(cfg, *speed);
    *width = wsg_bin_clamp(*width, 0.0f, cfg->stroke_mm);
    return motion_running(req) ? E_ALREADY_RUNNING : E_SUCCESS;
}

wsg_status_t wsg_bin_grasp(bin_req_t *req)
{
    float width = 0.0f;
    float speed = 0.0f;
    wsg_status_t status = width_speed(req, &width, &speed);
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_config_t *cfg = config(req);
    wsg_grip_args_t args = {cfg->default_force_n, true, width, speed, cfg->default_pwt_mm,
                            cfg->default_clt_mm};
    return pending(req, wsg_op_grip(req->dev, wsg_conn_owner(conn_public(req->bin->conn)), &args));
}

wsg_status_t wsg_bin_release(bin_req_t *req)
{
    float width = 0.0f;
    float speed = 0.0f;
    wsg_status_t status = width_speed(req, &width, &speed);
    if (status == E_SUCCESS) {
        status = check_width(config(req), &width);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    wsg_release_args_t args = {0.0f, speed, true, width};
    return pending(req,
                   wsg_op_release(req->dev, wsg_conn_owner(conn_public(req->bin->conn)), &args));
}

wsg_status_t wsg_bin_stop(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    return status != E_SUCCESS ? status : wsg_op_stop(req->dev);
}

wsg_status_t wsg_bin_fast_stop(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    return status != E_SUCCESS ? status : wsg_op_fast_stop(req->dev, "binary fast stop (0x23)");
}

/* The key "ack"; success also when nothing is latched (UMI sends it always). */
wsg_status_t wsg_bin_ack(bin_req_t *req)
{
    if (req->length != 3 || req->payload[0] != 'a' || req->payload[1] != 'c' ||
        req->payload[2] != 'k') {
        return E_CMD_FORMAT_ERROR;
    }
    return wsg_op_fsack(req->dev);
}
