/* SPDX-License-Identifier: BSD-3-Clause */
#include "app.h"

#include "hal_clock.h"
#include "sim/sim_models.h"
#include "sim/sim_world.h"
#include "wsg/wsg_runner.h"

/* The simulated axis is advanced on a 1 ms grid, like a 1 kHz servo loop.
 * Advancing it by a few microseconds at a time (each received byte could do
 * that) moves the jaws by less than a float ulp, so the model loses contact
 * with an end stop and homing never sees the axis blocked. */
#define WORLD_PERIOD_US 1000u

static wsg_device_t device;
static sim_world_t world;
static wsg_runner_t runner;
static uint64_t world_us;

static void advance_world(void *ctx, uint64_t now)
{
    (void)ctx;
    uint64_t behind = now - world_us;
    if (behind >= WORLD_PERIOD_US) {
        world_us = now - behind % WORLD_PERIOD_US;
        wsg_sim_world_advance(&world, world_us);
    }
}

void app_init(const wsg_proto_driver_t *const *drivers, size_t count)
{
    wsg_config_t cfg;
    wsg_sim_model_config(wsg_sim_model_default(), &cfg);
    uint64_t now = hal_clock_now_us();
    wsg_sim_world_init(&world, &cfg, now);
    wsg_hal_t hal;
    wsg_sim_world_hal(&world, &hal);
    wsg_device_init(&device, &cfg, &hal);
    wsg_conn_set_drivers(&device, drivers, count);
    world_us = now;
    wsg_runner_init(&runner, &device, advance_world, NULL);
}

wsg_device_t *app_device(void)
{
    return &device;
}

void app_feed(wsg_conn_t *c, const void *bytes, size_t len, bool end_of_datagram)
{
    wsg_runner_feed(&runner, c, bytes, len, end_of_datagram);
}

void app_poll(void)
{
    (void)wsg_runner_poll(&runner);
}
