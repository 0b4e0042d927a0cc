/* SPDX-License-Identifier: BSD-3-Clause */
#include "sim_models.h"

#include <string.h>

static const sim_model_t models[] = {
    /* datasheet figures given in the project brief */
    {"WSG 50-110", 110.0f, 5.0f, 420.0f, 100.0f, 5000.0f, 5.0f, 80.0f, 0.0f, false},
    /* estimates: the long-stroke variant of the WSG 50 */
    {"WSG 50-210", 210.0f, 5.0f, 420.0f, 100.0f, 5000.0f, 5.0f, 80.0f, 0.0f, true},
    /* estimates: the manual names a "WSG 32-068" */
    {"WSG 32-068", 68.0f, 5.0f, 400.0f, 100.0f, 5000.0f, 5.0f, 50.0f, 0.0f, true},
    /* estimates */
    {"WSG 25-064", 64.0f, 5.0f, 400.0f, 100.0f, 5000.0f, 5.0f, 20.0f, 0.0f, true},
};

unsigned wsg_sim_model_count(void)
{
    return (unsigned)(sizeof(models) / sizeof(models[0]));
}

const sim_model_t *wsg_sim_model_at(unsigned i)
{
    return i < wsg_sim_model_count() ? &models[i] : NULL;
}

const sim_model_t *wsg_sim_model_default(void)
{
    return &models[0];
}

/* Compares ignoring case, spaces and the "WSG" prefix. */
static void normalise(const char *in, char *out, size_t cap)
{
    size_t n = 0;
    if ((in[0] == 'w' || in[0] == 'W') && (in[1] == 's' || in[1] == 'S') &&
        (in[2] == 'g' || in[2] == 'G')) {
        in += 3;
    }
    for (; *in != '\0' && n + 1 < cap; in++) {
        if (*in != ' ') {
            out[n++] = *in;
        }
    }
    out[n] = '\0';
}

const sim_model_t *wsg_sim_model_find(const char *name)
{
    char wanted[32];
    normalise(name, wanted, sizeof(wanted));
    for (unsigned i = 0; i < wsg_sim_model_count(); i++) {
        char candidate[32];
        normalise(models[i].name, candidate, sizeof(candidate));
        /* "50-110" also matches "50" alone only when unambiguous: keep it exact */
        if (strcmp(wanted, candidate) == 0) {
            return &models[i];
        }
    }
    return NULL;
}

static void copy_string(char *dst, const char *src)
{
    strncpy(dst, src, WSG_CONFIG_STRING_MAX - 1);
    dst[WSG_CONFIG_STRING_MAX - 1] = '\0';
}

void wsg_sim_model_config(const sim_model_t *model, wsg_config_t *cfg)
{
    memset(cfg, 0, sizeof(*cfg));
    copy_string(cfg->devtype, model->name);
    copy_string(cfg->version, "4.0.0");
    copy_string(cfg->tag, "wsgsim");
    cfg->serial = 12345678u;
    cfg->hw_revision = 1u;
    cfg->stroke_mm = model->stroke_mm;
    cfg->speed_min_mm_s = model->speed_min_mm_s;
    cfg->speed_max_mm_s = model->speed_max_mm_s;
    cfg->accel_min_mm_s2 = model->accel_min_mm_s2;
    cfg->accel_max_mm_s2 = model->accel_max_mm_s2;
    cfg->force_min_n = model->force_min_n;
    cfg->force_max_n = model->force_max_n;
    cfg->force_overdrive_n = model->force_overdrive_n;
    cfg->default_speed_mm_s = model->speed_max_mm_s / 4.0f;
    cfg->default_accel_mm_s2 = model->accel_max_mm_s2 / 5.0f;
    cfg->default_force_n = model->force_max_n / 2.0f;
    cfg->default_pullback_mm = 10.0f;
    cfg->default_pwt_mm = 10.0f;
    cfg->default_clt_mm = 10.0f;
    cfg->soft_limit_minus_mm = 0.0f;
    cfg->soft_limit_plus_mm = model->stroke_mm;
    cfg->home_positive = true;
    cfg->homing_speed_mm_s = model->speed_max_mm_s / 8.0f;
    cfg->disconnect_raises_faststop = true;
    cfg->move_retarget = true;
    cfg->temp_warning_c = 60.0f;
    cfg->temp_fault_c = 70.0f;
}
