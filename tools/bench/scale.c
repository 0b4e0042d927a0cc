/* SPDX-License-Identifier: BSD-3-Clause */
/* Scaled clock: how closely simulated time follows SCALE times wall time
 * through wsgsim's control channel (docs/simctl.md). The e2e tests assert
 * only what holds at any machine speed (simulated durations); the rate is
 * measured here. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"

/* Sends a control command; its reply in reply (dies when there is none). */
static void control(conn_t *ctl, const char *cmd, char *reply, size_t cap)
{
    if (!conn_send(ctl, cmd) || !conn_read_line(ctl, reply, cap, 5000)) {
        die("control channel: no reply to %s", cmd);
    }
}

/* SIMTIME=[simulated ms,lag ms]: the simulated ms. */
static double simtime_ms(conn_t *ctl)
{
    char reply[128];
    control(ctl, "SIMTIME?", reply, sizeof(reply));
    if (strncmp(reply, "SIMTIME=[", 9) != 0) {
        die("SIMTIME? answered '%s'", reply);
    }
    return strtod(reply + 9, NULL);
}

static double measure_rate(conn_t *ctl, double scale, double seconds)
{
    char cmd[64];
    char reply[128];
    snprintf(cmd, sizeof(cmd), "SCALE=%g", scale);
    control(ctl, cmd, reply, sizeof(reply));
    if (strncmp(reply, "SCALE=", 6) != 0) {
        die("%s answered '%s'", cmd, reply);
    }
    double sim0 = simtime_ms(ctl);
    double wall0 = now_us();
    usleep((useconds_t)(seconds * 1e6));
    double sim1 = simtime_ms(ctl);
    double wall_ms = (now_us() - wall0) / 1000.0;
    return (sim1 - sim0) / wall_ms;
}

void scale_run(const server_t *srv, double seconds, scale_result_t *r)
{
    conn_t ctl = {.fd = tcp_connect(srv->ctl_port)};
    char reply[128];
    control(&ctl, "RESUME()", reply, sizeof(reply));
    for (int i = 0; i < SCALE_STEPS; i++) {
        r->rate[i] = measure_rate(&ctl, r->scale[i], seconds);
    }
    close(ctl.fd);
}
