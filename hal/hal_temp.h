/* SPDX-License-Identifier: BSD-3-Clause */
/* Controller board temperature sensor, per instance. */
#ifndef HAL_TEMP_H
#define HAL_TEMP_H

typedef struct {
    float (*board_c)(void *ctx);
} hal_temp_ops_t;

typedef struct {
    const hal_temp_ops_t *ops;
    void *ctx;
} hal_temp_t;

#endif
