/* SPDX-License-Identifier: BSD-3-Clause */
/* Motion configuration 0x30-0x38 (spec §5): device settings, shared with
 * GCL; acceleration and force are clamped to the device's limits. */
#include "bin/bin_internal.h"

static const wsg_config_t *config(const bin_req_t *req)
{
    return wsg_device_snapshot(req->dev)->config;
}

/* One float argument, clamped, then stored as the setting. */
static wsg_status_t set_clamped(bin_req_t *req, wsg_setting_t which, float low, float high)
{
    float value = 0.0f;
    wsg_status_t status = wsg_bin_expect_len(req, 4);
    if (status == E_SUCCESS) {
        status = wsg_bin_get_finite(req, 0, &value);
    }
    return status != E_SUCCESS ? status
                               : wsg_op_set(req->dev, which, wsg_bin_clamp(value, low, high));
}

wsg_status_t wsg_bin_set_acc(bin_req_t *req)
{
    const wsg_config_t *cfg = config(req);
    return set_clamped(req, WSG_SET_ACCEL, cfg->accel_min_mm_s2, cfg->accel_max_mm_s2);
}

wsg_status_t wsg_bin_get_acc(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    return status != E_SUCCESS ? status : wsg_bin_reply_f32(req, config(req)->default_accel_mm_s2);
}

wsg_status_t wsg_bin_set_force(bin_req_t *req)
{
    const wsg_config_t *cfg = config(req);
    return set_clamped(req, WSG_SET_FORCE_LIMIT, cfg->force_min_n, wsg_config_force_max(cfg));
}

wsg_status_t wsg_bin_get_force_limit(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    return status != E_SUCCESS ? status : wsg_bin_reply_f32(req, config(req)->default_force_n);
}

/* Both limits or none: the device state is left as it was on an error. */
wsg_status_t wsg_bin_set_soft_limits(bin_req_t *req)
{
    float minus = 0.0f;
    float plus = 0.0f;
    wsg_status_t status = wsg_bin_expect_len(req, 8);
    if (status == E_SUCCESS) {
        status = wsg_bin_get_finite(req, 0, &minus);
    }
    if (status == E_SUCCESS) {
        status = wsg_bin_get_finite(req, 4, &plus);
    }
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_config_t *cfg = config(req);
    if (minus < 0.0f || plus > cfg->stroke_mm || minus >= plus) {
        return E_RANGE_ERROR;
    }
    /* widen first so that neither step sees minus >= plus */
    wsg_op_set(req->dev, WSG_SET_SOFT_MINUS, 0.0f);
    wsg_op_set(req->dev, WSG_SET_SOFT_PLUS, plus);
    wsg_op_set(req->dev, WSG_SET_SOFT_MINUS, minus);
    return wsg_op_set(req->dev, WSG_SET_SOFT_LIMITS, 1.0f);
}

wsg_status_t wsg_bin_get_soft_limits(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    const wsg_config_t *cfg = config(req);
    if (!cfg->soft_limits_enabled) {
        return E_NOT_AVAILABLE;
    }
    uint8_t v[8];
    wsg_bin_put_f32(v, cfg->soft_limit_minus_mm);
    wsg_bin_put_f32(v + 4, cfg->soft_limit_plus_mm);
    return wsg_bin_reply_values(req, v, sizeof(v));
}

wsg_status_t wsg_bin_clear_soft_limits(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    return status != E_SUCCESS ? status : wsg_op_set(req->dev, WSG_SET_SOFT_LIMITS, 0.0f);
}

wsg_status_t wsg_bin_overdrive(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_len(req, 1);
    return status != E_SUCCESS
               ? status
               : wsg_op_set(req->dev, WSG_SET_OVERDRIVE, (req->payload[0] & 1u) ? 1.0f : 0.0f);
}

/* E_ACCESS_DENIED while holding a part (spec §5.1). */
wsg_status_t wsg_bin_tare(bin_req_t *req)
{
    wsg_status_t status = wsg_bin_expect_none(req);
    if (status != E_SUCCESS) {
        return status;
    }
    if (wsg_device_snapshot(req->dev)->grip_state == GS_HOLDING) {
        return E_ACCESS_DENIED;
    }
    return wsg_op_tare(req->dev, -1);
}
