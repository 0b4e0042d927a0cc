/* SPDX-License-Identifier: BSD-3-Clause */
/* Virtual-time speed: the device core linked in-process (libwsgfw.a, libwsgsim.a)
 * on a fake clock that jumps straight to each deadline the core asks for,
 * as a paused and stepped port would. HOME/MOVE/GRIP/RELEASE cycles on a
 * part of PART_MM between the jaws. */
#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "hal_clock.h"
#include "hal_log.h"
#include "sim_models.h"
#include "sim_world.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_gcl.h"

#define PART_MM 30.0f
#define PART_STIFFNESS 100.0f
#define COMMAND_TIMEOUT_US 30000000u
#define START_US 1000000u

static uint64_t fake_now_us;
static char last_final[WSG_REPLY_MAX + 1];

uint64_t hal_clock_now_us(void)
{
    return fake_now_us;
}

void hal_log(hal_log_level_t level, const char *message)
{
    (void)level;
    (void)message;
}

/* Keeps the last FIN/ERR line. */
static void capture(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    (void)ctx;
    if (kind == WSG_MSG_REPLY && len > 4 &&
        (memcmp(line, "FIN ", 4) == 0 || memcmp(line, "ERR ", 4) == 0)) {
        memcpy(last_final, line, len - 1);
        last_final[len - 1] = '\0';
    }
}

static const wsg_conn_io_t capture_io = {.write = capture};
static sim_world_t world;

static void step_to_deadline(wsg_device_t *dev, long *steps)
{
    uint64_t next = wsg_device_next_deadline_us(dev);
    fake_now_us = next > fake_now_us ? next : fake_now_us + 1u;
    wsg_sim_world_advance(&world, fake_now_us);
    wsg_device_step(dev);
    (*steps)++;
}

/* Sends a long command and steps until its FIN; false on ERR or timeout. */
static bool run_command(wsg_device_t *dev, wsg_conn_t *s, const char *line, const char *name,
                        long *steps)
{
    char fin[64];
    snprintf(fin, sizeof(fin), "FIN %s", name);
    last_final[0] = '\0';
    wsg_sim_world_advance(&world, fake_now_us);
    wsg_conn_input(s, (const uint8_t *)line, strlen(line));
    uint64_t deadline = fake_now_us + COMMAND_TIMEOUT_US;
    while (last_final[0] == '\0' && fake_now_us < deadline) {
        step_to_deadline(dev, steps);
    }
    return strcmp(last_final, fin) == 0;
}

static bool run_cycle(wsg_device_t *dev, wsg_conn_t *s, long *steps)
{
    return run_command(dev, s, "HOME()\n", "HOME", steps) &&
           run_command(dev, s, "MOVE(80)\n", "MOVE", steps) &&
           run_command(dev, s, "GRIP(20)\n", "GRIP", steps) &&
           run_command(dev, s, "RELEASE(10)\n", "RELEASE", steps);
}

void vtime_run(int cycles, vtime_result_t *r)
{
    static wsg_device_t dev;
    static wsg_conn_t conn;
    wsg_config_t cfg;
    wsg_sim_model_config(wsg_sim_model_default(), &cfg);
    fake_now_us = START_US;
    wsg_sim_world_init(&world, &cfg, fake_now_us);
    wsg_sim_axis_place_part(&world.axis, PART_MM, PART_STIFFNESS);
    wsg_hal_t hal;
    wsg_sim_world_hal(&world, &hal);
    wsg_device_init(&dev, &cfg, &hal);
    wsg_conn_t *s = &conn;
    wsg_conn_open(s, &dev, &wsg_gcl_driver, WSG_TRANSPORT_STREAM, &capture_io, NULL);
    memset(r, 0, sizeof(*r));
    double t0 = now_us();
    for (int i = 0; i < cycles; i++) {
        if (run_cycle(&dev, s, &r->steps)) {
            r->cycles_done++;
        } else {
            r->cycles_failed++;
            fprintf(stderr, "wsgbench: virtual-time cycle %d failed: '%s'\n", i, last_final);
        }
    }
    r->wall_s = (now_us() - t0) / 1e6;
    r->virtual_s = (double)(fake_now_us - START_US) / 1e6;
}
