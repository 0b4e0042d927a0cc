/* The simulated world behind the HAL: device configuration, mechanics and
 * thermal model. Implements hal_axis.h, hal_temp.h and hal_device.h for any
 * target without a real motor. The port advances it to the clock's time
 * before every device step. */
#ifndef SIM_WORLD_H
#define SIM_WORLD_H

#include <stdint.h>

#include "hal_device.h"
#include "sim_axis.h"
#include "sim_thermal.h"

typedef struct {
    hal_device_config_t config;
    sim_axis_t axis;
    sim_thermal_t thermal;
    uint64_t last_us;
} sim_world_t;

sim_world_t *sim_world(void);

/* Power-on: a device with this configuration, the jaws mid-stroke. */
void sim_world_init(const hal_device_config_t *config, uint64_t now_us);

/* Integrates mechanics and temperature up to now_us. */
void sim_world_advance(uint64_t now_us);

#endif
