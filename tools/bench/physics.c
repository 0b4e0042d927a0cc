/* SPDX-License-Identifier: BSD-3-Clause */
/* The gripper in the default physics scene (--physics mujoco,
 * docs/physics.md): a grip cycle on the paused clock (home, grip the box,
 * hold 1 s, release), and the running clock's pace with the engine in it
 * (grip and release cycles at 1x), with wsgsim's share of one core. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"

#define REPLY_MS 30000
#define RUNNING_CYCLES 3

static void expect(conn_t *c, const char *send, const char *prefix)
{
    char line[256] = "";
    if (!conn_send(c, send) || !conn_read_line(c, line, sizeof(line), REPLY_MS) ||
        strncmp(line, prefix, strlen(prefix)) != 0) {
        die("physics: %s answered '%s'", send, line);
    }
}

/* A long command to its FIN on the paused clock (RUN_UNTIL_DONE). */
static void paused_command(conn_t *gcl, conn_t *ctl, const char *cmd, const char *fin)
{
    char line[256] = "";
    expect(gcl, cmd, "ACK ");
    expect(ctl, "RUN_UNTIL_DONE(30000)", "RUN_UNTIL_DONE=");
    if (!conn_read_line(gcl, line, sizeof(line), REPLY_MS) || strcmp(line, fin) != 0) {
        die("physics: %s ended with '%s'", cmd, line);
    }
}

static bool start(server_t *srv, const char *wsgsim, const char *out_dir, bool paused)
{
    const char *argv[48];
    int n = wsgsim_argv(argv, 44, wsgsim, paused);
    argv[n++] = "--physics";
    argv[n++] = "mujoco";
    if (!paused) { /* the paused server has its control channel already */
        argv[n++] = "--sim-port";
        argv[n++] = "0";
    }
    argv[n] = NULL;
    char log_path[512];
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-physics.log", out_dir);
    return server_start_cmd(srv, "wsgsim", argv, log_path, 30.0) && srv->ctl_port != 0;
}

static void paused_cycles(const char *wsgsim, const char *out_dir, physics_result_t *r)
{
    server_t srv;
    if (!start(&srv, wsgsim, out_dir, true)) {
        die("%s did not start with --physics mujoco", wsgsim);
    }
    conn_t gcl = {.fd = tcp_connect(srv.tcp_port)};
    conn_t ctl = {.fd = tcp_connect(srv.ctl_port)};
    double t0 = now_us();
    for (int i = 0; i < PHYSICS_PAUSED_CYCLES; i++) {
        paused_command(&gcl, &ctl, "HOME()", "FIN HOME");
        paused_command(&gcl, &ctl, "GRIP(40,40)", "FIN GRIP");
        expect(&ctl, "STEP(1000)", "STEP=");
        paused_command(&gcl, &ctl, "RELEASE()", "FIN RELEASE");
    }
    r->paused_cycle_s = (now_us() - t0) / 1e6 / PHYSICS_PAUSED_CYCLES;
    close(gcl.fd);
    close(ctl.fd);
    server_stop(&srv);
}

static double simtime_s(conn_t *ctl)
{
    char line[256] = "";
    double ms = -1.0;
    if (!conn_send(ctl, "SIMTIME?") || !conn_read_line(ctl, line, sizeof(line), REPLY_MS) ||
        sscanf(line, "SIMTIME=[%lf", &ms) != 1) {
        die("physics: SIMTIME? answered '%s'", line);
    }
    return ms / 1e3;
}

static void running_cycles(const char *wsgsim, const char *out_dir, physics_result_t *r)
{
    server_t srv;
    if (!start(&srv, wsgsim, out_dir, false)) {
        die("%s did not start with --physics mujoco", wsgsim);
    }
    conn_t gcl = {.fd = tcp_connect(srv.tcp_port)};
    conn_t ctl = {.fd = tcp_connect(srv.ctl_port)};
    expect(&gcl, "HOME()", "ACK HOME");
    usleep(1500000);
    double sim0 = simtime_s(&ctl);
    double cpu0 = proc_cpu_us(srv.pid);
    double t0 = now_us();
    for (int i = 0; i < RUNNING_CYCLES; i++) {
        expect(&gcl, "GRIP(40,40)", "");
        usleep(1500000);
        expect(&gcl, "RELEASE()", "");
        usleep(500000);
    }
    double wall = (now_us() - t0) / 1e6;
    r->running_rate = (simtime_s(&ctl) - sim0) / wall;
    r->running_cpu_pct = 100.0 * (proc_cpu_us(srv.pid) - cpu0) / 1e6 / wall;
    close(gcl.fd);
    close(ctl.fd);
    server_stop(&srv);
}

void physics_run(const char *wsgsim, const char *out_dir, physics_result_t *r)
{
    memset(r, 0, sizeof(*r));
    paused_cycles(wsgsim, out_dir, r);
    running_cycles(wsgsim, out_dir, r);
    r->measured = true;
}
