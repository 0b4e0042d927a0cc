/* SPDX-License-Identifier: BSD-3-Clause */
/* Instructions the server executes per request, counted by callgrind: the
 * server runs under `valgrind --tool=callgrind` while one TCP client sends
 * POS? sequentially (one in flight) and then pipelined (batches written at
 * once). Start-up, connection and shutdown cost the same in every run, so
 * three runs that differ only in the number of requests give the cost of
 * one request as a difference:
 *   base:       SEQ_BASE sequential, PIPE_BASE pipelined
 *   sequential: SEQ_BASE + n sequential, PIPE_BASE pipelined
 *   pipelined:  SEQ_BASE sequential, PIPE_BASE + m pipelined
 * wsgsim runs with its clock paused (--start-paused): no simulated time
 * passes, so no timer work (finger bus, idle tick) lands in the count, which
 * would grow with the wall time a run takes under callgrind.
 *
 * A second wsgsim runs with its clock running, as a user's does: its
 * sequential count includes the work each wake-up does besides the request
 * (the scheduler's pass), but not the timers that fall due while callgrind
 * slows the run down. Those are measured apart, as instructions per wall
 * second of a connected client that sends nothing (one more run that only
 * waits IDLE_S), and the wall time of the sequential run times that rate is
 * taken off. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"

#define SEQ_BASE 200
#define PIPE_BASE 1000
#define PIPE_BATCH 100
#define REPLY_TIMEOUT_MS 60000
#define CALLGRIND_START_S 120.0
#define CALLGRIND_STOP_S 120.0
#define IDLE_S 2.0

typedef struct {
    const char *name;           /* "wsgsim" or "echo" */
    const char *const *command; /* the server's own command line */
    const char *out_dir;
} counted_server_t;

static void expect_reply(conn_t *c, const char *name)
{
    char line[256];
    if (!conn_read_line(c, line, sizeof(line), REPLY_TIMEOUT_MS) || strncmp(line, "POS", 3) != 0) {
        die("%s under callgrind: no reply to POS?", name);
    }
}

static void send_sequential(conn_t *c, const char *name, int count)
{
    for (int i = 0; i < count; i++) {
        if (!conn_send(c, "POS?")) {
            die("%s under callgrind: send failed", name);
        }
        expect_reply(c, name);
    }
}

static void send_pipelined(conn_t *c, const char *name, int count)
{
    static const char line[] = "POS?\n";
    char batch[PIPE_BATCH * (sizeof(line) - 1)];
    for (int i = 0; i < PIPE_BATCH; i++) {
        memcpy(batch + i * (sizeof(line) - 1), line, sizeof(line) - 1);
    }
    for (int done = 0; done < count; done += PIPE_BATCH) {
        int n = count - done < PIPE_BATCH ? count - done : PIPE_BATCH;
        size_t len = (size_t)n * (sizeof(line) - 1);
        if (write(c->fd, batch, len) != (ssize_t)len) {
            die("%s under callgrind: send failed", name);
        }
        for (int i = 0; i < n; i++) {
            expect_reply(c, name);
        }
    }
}

double callgrind_total(const char *path)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        die("callgrind wrote no %s", path);
    }
    char line[512];
    double total = -1.0;
    while (total < 0 && fgets(line, sizeof(line), f) != NULL) {
        if (strncmp(line, "summary:", 8) == 0) {
            total = strtod(line + 8, NULL);
        } else if (strncmp(line, "totals:", 7) == 0) {
            total = strtod(line + 7, NULL);
        }
    }
    fclose(f);
    if (total <= 0) {
        die("no instruction total in %s", path);
    }
    return total;
}

/* Instructions of one whole run; *wall_s: how long its client phase took
 * (the idle wait, the sequential and the pipelined requests), unless NULL. */
static double counted_run(const counted_server_t *s, int sequential, int pipelined, double idle_s,
                          double *wall_s)
{
    char out_opt[600];
    char out_path[512];
    char log_path[512];
    snprintf(out_path, sizeof(out_path), "%s/callgrind.%s.%d.%d.%.0f.out", s->out_dir, s->name,
             sequential, pipelined, idle_s);
    snprintf(out_opt, sizeof(out_opt), "--callgrind-out-file=%s", out_path);
    snprintf(log_path, sizeof(log_path), "%s/callgrind.%s.log", s->out_dir, s->name);
    const char *argv[64] = {"valgrind", "--tool=callgrind", out_opt};
    int n = 3;
    for (int i = 0; s->command[i] != NULL && n < 63; i++) {
        argv[n++] = s->command[i];
    }
    argv[n] = NULL;
    unlink(out_path);
    server_t srv;
    if (!server_start_cmd(&srv, s->name, argv, log_path, CALLGRIND_START_S)) {
        die("%s did not start under callgrind (is valgrind installed? see %s)", s->name, log_path);
    }
    conn_t c = {.fd = tcp_connect(srv.tcp_port)};
    double started_us = now_us();
    usleep((useconds_t)(idle_s * 1e6));
    send_sequential(&c, s->name, sequential);
    send_pipelined(&c, s->name, pipelined);
    if (wall_s != NULL) {
        *wall_s = (now_us() - started_us) / 1e6;
    }
    if (!server_stop_within(&srv, CALLGRIND_STOP_S)) {
        die("%s under callgrind did not exit on SIGTERM (see %s)", s->name, log_path);
    }
    close(c.fd);
    return callgrind_total(out_path);
}

static void count_server(const counted_server_t *s, int seq_n, int pipe_n, double *per_seq,
                         double *per_pipe)
{
    fprintf(stderr, "wsgbench: callgrind, %s: base, +%d sequential, +%d pipelined POS?\n", s->name,
            seq_n, pipe_n);
    double base = counted_run(s, SEQ_BASE, PIPE_BASE, 0, NULL);
    double seq = counted_run(s, SEQ_BASE + seq_n, PIPE_BASE, 0, NULL);
    double pipe = counted_run(s, SEQ_BASE, PIPE_BASE + pipe_n, 0, NULL);
    *per_seq = (seq - base) / seq_n;
    *per_pipe = (pipe - base) / pipe_n;
}

/* The running clock's sequential POS?, less the timers of the run's wall
 * time (see the top of this file). */
static double count_running(const counted_server_t *s, int seq_n, double *idle_per_s)
{
    fprintf(stderr, "wsgbench: callgrind, %s: base, +%.0f s idle, +%d sequential POS?\n", s->name,
            IDLE_S, seq_n);
    double wall_base, wall_idle, wall_seq;
    double base = counted_run(s, SEQ_BASE, PIPE_BASE, 0, &wall_base);
    double idle = counted_run(s, SEQ_BASE, PIPE_BASE, IDLE_S, &wall_idle);
    double seq = counted_run(s, SEQ_BASE + seq_n, PIPE_BASE, 0, &wall_seq);
    *idle_per_s = (idle - base) / (wall_idle - wall_base);
    return (seq - base - *idle_per_s * (wall_seq - wall_base)) / seq_n;
}

void instr_run(const char *wsgsim, const char *self_exe, const char *out_dir, int seq_n, int pipe_n,
               instr_result_t *r)
{
    const char *wsg_cmd[48];
    wsgsim_argv(wsg_cmd, 48, wsgsim, true);
    const char *const echo_cmd[] = {self_exe, "--serve-echo", NULL};
    const counted_server_t servers[2] = {{"wsgsim", wsg_cmd, out_dir}, {"echo", echo_cmd, out_dir}};
    for (int k = 0; k < 2; k++) {
        count_server(&servers[k], seq_n, pipe_n, &r->sequential[k], &r->pipelined[k]);
    }
    const char *running_cmd[48];
    wsgsim_argv(running_cmd, 48, wsgsim, false);
    const counted_server_t running = {"wsgsim-running", running_cmd, out_dir};
    r->sequential_running = count_running(&running, seq_n, &r->running_idle_per_s);
}
