/* SPDX-License-Identifier: BSD-3-Clause */
/* The hardware one device instance drives: its axis, its temperature sensor
 * and its CAN controller (NULL: no finger bus). Clock and log are link-time
 * (hal_clock.h, hal_log.h): one per process, shared by every instance. */
#ifndef HAL_H
#define HAL_H

#include "hal_axis.h"
#include "hal_can.h"
#include "hal_temp.h"

typedef struct {
    hal_axis_t axis;
    hal_temp_t temp;
    hal_can_t can; /* can.ops NULL: no finger bus */
} wsg_hal_t;

#endif
