/* SPDX-License-Identifier: BSD-3-Clause */
/* Virtual-time speed through wsgsim itself: started with --start-paused and
 * a control channel (docs/simctl.md), a driver sends each GCL command and
 * then STEP(step_ms) on the control channel until the command's FIN, or
 * (step_ms 0) RUN_UNTIL_DONE once: one control round trip per command. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"

#define STEPS_PER_COMMAND_MAX 600
#define STR_(x) #x
#define STR(x) STR_(x)

static bool final_seen(conn_t *gcl, const char *name, bool *failed)
{
    char line[256];
    while (conn_read_line(gcl, line, sizeof(line), 0)) {
        if (strncmp(line, "FIN ", 4) == 0 && strcmp(line + 4, name) == 0) {
            return true;
        }
        if (strncmp(line, "ERR ", 4) == 0) {
            fprintf(stderr, "wsgbench: %s answered '%s'\n", name, line);
            *failed = true;
            return true;
        }
    }
    return false;
}

/* Returns the simulated ms it took (in whole steps); -1 on failure. */
static double run_command(conn_t *gcl, conn_t *ctl, const char *cmd, const char *name, int step_ms)
{
    char step[32];
    char reply[256];
    snprintf(step, sizeof(step), "STEP(%d)", step_ms);
    if (!conn_send(gcl, cmd)) {
        return -1;
    }
    bool failed = false;
    for (int i = 1; i <= STEPS_PER_COMMAND_MAX; i++) {
        if (!conn_send(ctl, step) || !conn_read_line(ctl, reply, sizeof(reply), 5000) ||
            strncmp(reply, "STEP=", 5) != 0) {
            die("control channel: %s answered '%s'", step, reply);
        }
        if (final_seen(gcl, name, &failed)) {
            return failed ? -1.0 : (double)i * step_ms;
        }
    }
    return -1.0;
}

#define RUN_LIMIT_MS 30000
/* The fingers' start-up (power, then their configuration) is over by then. */
#define FINGERS_UP_MS 1000

/* RUN_UNTIL_DONE=[ms,"why"]: the simulated ms reached; -1 unless "done". */
static double run_until_done(conn_t *ctl)
{
    char reply[256];
    double ms = -1.0;
    char why[16] = "";
    if (!conn_send(ctl, "RUN_UNTIL_DONE(" STR(RUN_LIMIT_MS) ")") ||
        !conn_read_line(ctl, reply, sizeof(reply), 5000) ||
        sscanf(reply, "RUN_UNTIL_DONE=[%lf,\"%15[a-z]\"]", &ms, why) != 2) {
        die("control channel: RUN_UNTIL_DONE answered '%s'", reply);
    }
    return strcmp(why, "done") == 0 ? ms : -1.0;
}

/* The simulated ms the command took, from the server's own times; -1 on
 * failure. */
static double run_command_until_done(conn_t *gcl, conn_t *ctl, const char *cmd, const char *name,
                                     double *sim_now_ms)
{
    char line[256];
    if (!conn_send(gcl, cmd) || !conn_read_line(gcl, line, sizeof(line), 5000) ||
        strncmp(line, "ACK ", 4) != 0) {
        return -1.0;
    }
    double done_ms = run_until_done(ctl);
    char fin[64];
    snprintf(fin, sizeof(fin), "FIN %s", name);
    /* the FIN was sent before the control reply */
    if (done_ms < 0 || !conn_read_line(gcl, line, sizeof(line), 5000) || strcmp(line, fin) != 0) {
        fprintf(stderr, "wsgbench: %s: expected '%s', got '%s'\n", cmd, fin, line);
        return -1.0;
    }
    double took = done_ms - *sim_now_ms;
    *sim_now_ms = done_ms;
    return took;
}

/* sim_now_ms: where the server's clock stands (RUN_UNTIL_DONE only). */
static bool run_cycle(conn_t *gcl, conn_t *ctl, int step_ms, double *sim_ms, double *sim_now_ms)
{
    static const char *const cmds[4][2] = {
        {"HOME()", "HOME"}, {"MOVE(80)", "MOVE"}, {"GRIP(20)", "GRIP"}, {"RELEASE(10)", "RELEASE"}};
    for (int i = 0; i < 4; i++) {
        double ms = step_ms > 0
                        ? run_command(gcl, ctl, cmds[i][0], cmds[i][1], step_ms)
                        : run_command_until_done(gcl, ctl, cmds[i][0], cmds[i][1], sim_now_ms);
        if (ms < 0) {
            return false;
        }
        *sim_ms += ms;
    }
    return true;
}

void vtime_session_open(vtime_session_t *s, const server_t *srv)
{
    *s = (vtime_session_t){.gcl = {.fd = tcp_connect(srv->tcp_port)},
                           .ctl = {.fd = tcp_connect(srv->ctl_port)},
                           .sim_now_ms = 0}; /* started paused at 0 */
}

void vtime_session_run(vtime_session_t *s, int cycles, int step_ms, vtime_result_t *r)
{
    double sim_ms = 0;
    int done = 0;
    double t0 = now_us();
    for (int i = 0; i < cycles; i++) {
        if (run_cycle(&s->gcl, &s->ctl, step_ms, &sim_ms, &s->sim_now_ms)) {
            done++;
        } else {
            r->cycles_failed++;
        }
    }
    r->wall_s += (now_us() - t0) / 1e6;
    r->cycles_done += done;
    r->virtual_s += sim_ms / 1e3;
    r->steps += step_ms > 0 ? (long)(sim_ms / step_ms) : 4L * done;
}

void vtime_session_close(vtime_session_t *s)
{
    conn_send(&s->gcl, "BYE()");
    close(s->gcl.fd);
    close(s->ctl.fd);
}

/* Waits long for one reply: the server may run under callgrind. */
#define SLOW_REPLY_MS 120000

static void command_done(conn_t *gcl, conn_t *ctl, const char *cmd, const char *fin)
{
    char line[256];
    if (!conn_send(gcl, cmd) || !conn_read_line(gcl, line, sizeof(line), SLOW_REPLY_MS) ||
        strncmp(line, "ACK ", 4) != 0) {
        die("hold the part: %s answered '%s'", cmd, line);
    }
    if (!conn_send(ctl, "RUN_UNTIL_DONE(" STR(RUN_LIMIT_MS) ")") ||
        !conn_read_line(ctl, line, sizeof(line), SLOW_REPLY_MS) ||
        strstr(line, "\"done\"") == NULL) {
        die("hold the part: RUN_UNTIL_DONE after %s answered '%s'", cmd, line);
    }
    if (!conn_read_line(gcl, line, sizeof(line), SLOW_REPLY_MS) || strcmp(line, fin) != 0) {
        die("hold the part: %s ended with '%s'", cmd, line);
    }
}

void vtime_hold_part(const server_t *srv)
{
    vtime_session_t s;
    char reply[256];
    vtime_session_open(&s, srv);
    if (!conn_send(&s.ctl, "STEP(" STR(FINGERS_UP_MS) ")") ||
        !conn_read_line(&s.ctl, reply, sizeof(reply), SLOW_REPLY_MS) ||
        strncmp(reply, "STEP=", 5) != 0) {
        die("hold the part: STEP answered '%s'", reply);
    }
    command_done(&s.gcl, &s.ctl, "HOME()", "FIN HOME");
    command_done(&s.gcl, &s.ctl, "GRIP(20)", "FIN GRIP");
    vtime_session_close(&s);
}

void vtime_ctl_run(const server_t *srv, int cycles, int step_ms, vtime_result_t *r)
{
    vtime_session_t s;
    memset(r, 0, sizeof(*r));
    vtime_session_open(&s, srv);
    vtime_session_run(&s, cycles, step_ms, r);
    vtime_session_close(&s);
}
