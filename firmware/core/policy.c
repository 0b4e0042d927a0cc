/* SPDX-License-Identifier: BSD-3-Clause */
/* The device's range and policy rules (wsg_config.h), in one place. */
#include "wsg/wsg_config.h"

static bool in_range(float value, float min, float max)
{
    return value >= min && value <= max;
}

float wsg_config_force_max(const wsg_config_t *cfg)
{
    return cfg->overdrive_mode && cfg->force_overdrive_n > 0.0f ? cfg->force_overdrive_n
                                                                : cfg->force_max_n;
}

bool wsg_config_force_ok(const wsg_config_t *cfg, float force_n)
{
    return in_range(force_n, cfg->force_min_n, wsg_config_force_max(cfg));
}

bool wsg_config_speed_ok(const wsg_config_t *cfg, float speed_mm_s)
{
    return in_range(speed_mm_s, cfg->speed_min_mm_s, cfg->speed_max_mm_s);
}

bool wsg_config_accel_ok(const wsg_config_t *cfg, float accel_mm_s2)
{
    return in_range(accel_mm_s2, cfg->accel_min_mm_s2, cfg->accel_max_mm_s2);
}

void wsg_config_travel(const wsg_config_t *cfg, float *low_mm, float *high_mm)
{
    *low_mm = cfg->soft_limits_enabled ? cfg->soft_limit_minus_mm : 0.0f;
    *high_mm = cfg->soft_limits_enabled ? cfg->soft_limit_plus_mm : cfg->stroke_mm;
}

bool wsg_config_target_ok(const wsg_config_t *cfg, float target_mm)
{
    float low = 0.0f;
    float high = 0.0f;
    wsg_config_travel(cfg, &low, &high);
    return in_range(target_mm, low, high);
}

bool wsg_config_length_ok(const wsg_config_t *cfg, float mm)
{
    return in_range(mm, 0.0f, cfg->stroke_mm);
}

bool wsg_config_text_char_ok(char c)
{
    return c >= 0x20 && c <= 0x7e && c != '"';
}

bool wsg_config_check(const wsg_config_t *cfg, const char **why)
{
    if (!wsg_config_length_ok(cfg, cfg->soft_limit_minus_mm) ||
        !wsg_config_length_ok(cfg, cfg->soft_limit_plus_mm)) {
        *why = "soft limits must lie within the stroke";
        return false;
    }
    if (cfg->soft_limit_minus_mm >= cfg->soft_limit_plus_mm) {
        *why = "soft_limit_minus must be below soft_limit_plus";
        return false;
    }
    return true;
}
