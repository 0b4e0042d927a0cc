/* SPDX-License-Identifier: BSD-3-Clause */
/* Timing profiles (docs/timing.md): 1,000 POS? requests on the paused
 * clock, each run exactly with RUN_UNTIL_DONE, under --timing wsg50 and
 * under the default ideal profile. The wall time of the wsg50 run (the
 * waiting is simulated time, not work), and wsgsim's own CPU time per
 * request under both: a profile must not make a request cost more. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"

#define REPLY_MS 10000
#define TIMING_REQUESTS 1000
#define IDLE_RETRIES 100000

/* Sends line on the control channel and reads its one reply. */
static void control(conn_t *ctl, const char *line, char *reply, size_t cap)
{
    if (!conn_send(ctl, line) || !conn_read_line(ctl, reply, cap, REPLY_MS)) {
        die("timing: %s got no reply", line);
    }
}

/* One POS? served: under a profile RUN_UNTIL_DONE runs until the device
 * has served it ("idle" while the request has not reached it yet). */
static void one_request(conn_t *gcl, conn_t *ctl, bool timed)
{
    char line[128];
    if (!conn_send(gcl, "POS?")) {
        die("timing: cannot send POS?");
    }
    for (int i = 0; i < IDLE_RETRIES; i++) {
        control(ctl, "RUN_UNTIL_DONE(1000)", line, sizeof(line));
        if (!timed || strstr(line, "\"idle\"") == NULL) {
            break;
        }
    }
    if (!conn_read_line(gcl, line, sizeof(line), REPLY_MS) || strncmp(line, "POS=", 4) != 0) {
        die("timing: POS? answered '%s'", line);
    }
}

/* The run under one profile: wall s and wsgsim's CPU µs per request. */
static void run_profile(const char *wsgsim, const char *out, const char *profile, double *wall_s,
                        double *cpu_us)
{
    const char *argv[48];
    int n = wsgsim_argv(argv, 40, wsgsim, true);
    argv[n++] = "--timing";
    argv[n++] = profile;
    argv[n] = NULL;
    char log_path[512];
    server_t srv;
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-timing-%s.log", out, profile);
    if (!server_start_cmd(&srv, "wsgsim", argv, log_path, 30.0) || srv.ctl_port == 0) {
        die("%s did not start paused with --timing %s (see %s)", wsgsim, profile, log_path);
    }
    conn_t gcl = {.fd = tcp_connect(srv.tcp_port)};
    conn_t ctl = {.fd = tcp_connect(srv.ctl_port)};
    bool timed = strcmp(profile, "ideal") != 0;
    one_request(&gcl, &ctl, timed); /* warm-up */
    double cpu0 = proc_cpu_us(srv.pid);
    double t0 = now_us();
    for (int i = 0; i < TIMING_REQUESTS; i++) {
        one_request(&gcl, &ctl, timed);
    }
    *wall_s = (now_us() - t0) / 1e6;
    *cpu_us = (proc_cpu_us(srv.pid) - cpu0) / TIMING_REQUESTS;
    close(gcl.fd);
    close(ctl.fd);
    server_stop(&srv);
}

void timing_run(const char *wsgsim, const char *out, timing_result_t *r)
{
    r->requests = TIMING_REQUESTS;
    run_profile(wsgsim, out, "wsg50", &r->wsg50_wall_s, &r->wsg50_cpu_us);
    run_profile(wsgsim, out, "ideal", &r->ideal_wall_s, &r->ideal_cpu_us);
}
