/* Device identity and configuration: what the real WSG keeps in its
 * configuration memory and edits through its web interface. */
#ifndef HAL_DEVICE_H
#define HAL_DEVICE_H

#include <stdbool.h>
#include <stdint.h>

#define HAL_DEVICE_STRING_MAX 48

typedef struct {
    /* identity */
    char devtype[HAL_DEVICE_STRING_MAX]; /* e.g. "WSG 50-110" */
    char version[HAL_DEVICE_STRING_MAX]; /* firmware version string, e.g. "4.0.0" */
    char tag[HAL_DEVICE_STRING_MAX];     /* descriptor string (device tag) */
    uint32_t serial;

    /* mechanics of the model */
    float stroke_mm;
    float speed_min_mm_s, speed_max_mm_s;
    float accel_min_mm_s2, accel_max_mm_s2;
    float force_min_n, force_max_n; /* nominal gripping force range */
    float force_overdrive_n;        /* 0: the model has no overdrive mode */
    bool overdrive_mode;            /* overdrive enabled in the configuration */

    /* motion configuration (web interface "Motion Configuration") */
    float default_speed_mm_s;
    float default_accel_mm_s2;
    float default_force_n;
    float default_pullback_mm;
    float default_pwt_mm; /* part width tolerance */
    float default_clt_mm; /* clamping travel */
    bool soft_limits_enabled;
    float soft_limit_minus_mm, soft_limit_plus_mm;
    bool home_positive; /* default homing direction */
    float homing_speed_mm_s;

    /* behaviour */
    bool disconnect_raises_faststop;
    bool move_retarget; /* a MOVE during a MOVE retargets it; false: ERR MOVE 4 */
    float temp_warning_c, temp_fault_c;
} hal_device_config_t;

/* The active configuration; the core reads it whenever it needs a value. */
const hal_device_config_t *hal_device_config(void);

#endif
