/* SPDX-License-Identifier: BSD-3-Clause */
/* The recording proxy (build/wsgproxy, docs/calibration.md): what it adds
 * to a GCL round trip, and that a driver's full-rate polling loses nothing
 * through it. One free-running wsgsim; POS? round trips taken in turn,
 * one directly and one through a proxy that records, so that a busy
 * moment of the machine hits both alike; the added p50 and p99 are the
 * differences of the quantiles. Then POS? pipelined through the proxy as fast as the client
 * can write: every request answered, and in the record both ways. */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bench.h"

#define PROXY_BLOCK 1 /* round trips each way in turn */
#define PROXY_WARMUP 500
#define PIPELINED 20000
#define REPLY_MS 10000

static void start_proxy(server_t *px, const server_t *sim, const char *wsgproxy,
                        const char *out_dir, char *record, size_t cap)
{
    char log_path[512], tcp[16], udp[16];
    snprintf(log_path, sizeof(log_path), "%s/wsgproxy.log", out_dir);
    snprintf(record, cap, "%s/wsgproxy-record.txt", out_dir);
    snprintf(tcp, sizeof(tcp), "%d", sim->tcp_port);
    snprintf(udp, sizeof(udp), "%d", sim->udp_port);
    const char *argv[] = {wsgproxy,    "--gripper",
                          "127.0.0.1", "--gripper-tcp-port",
                          tcp,         "--gripper-udp-port",
                          udp,         "--listen",
                          "127.0.0.1", "--tcp-port",
                          "0",         "--udp-port",
                          "0",         "--binary-udp-port",
                          "off",       "--record",
                          record,      NULL};
    if (!server_start_cmd(px, "wsgproxy", argv, log_path, 30.0)) {
        die("%s did not start (see %s)", wsgproxy, log_path);
    }
}

static void round_trips(conn_t *c, int n, samples_t *out)
{
    for (int i = 0; i < n; i++) {
        double us;
        if (!rtt_tcp(c, "POS?", &us)) {
            die("proxy: POS? got no answer");
        }
        if (out != NULL) {
            samples_add(out, us);
        }
    }
}

/* Requests written back to back, replies read meanwhile: the count answered. */
static long pipelined(int port)
{
    conn_t c = {.fd = tcp_connect(port)};
    static char requests[PIPELINED * 5];
    for (int i = 0; i < PIPELINED; i++) {
        memcpy(requests + 5 * i, "POS?\n", 5);
    }
    if (send(c.fd, requests, sizeof(requests), MSG_NOSIGNAL) != (ssize_t)sizeof(requests)) {
        die("proxy: cannot send the pipelined requests");
    }
    long answered = 0;
    char line[64];
    while (answered < PIPELINED && conn_read_line(&c, line, sizeof(line), REPLY_MS)) {
        answered++;
    }
    close(c.fd);
    return answered;
}

/* Record lines of POS? sent ('>') and its answers ('<'). */
static void count_record(const char *path, long *sent, long *answered)
{
    FILE *f = fopen(path, "r");
    char line[512];
    *sent = *answered = 0;
    while (f != NULL && fgets(line, sizeof(line), f) != NULL) {
        *sent += strstr(line, " > POS?\n") != NULL;
        *answered += strstr(line, " < POS=") != NULL;
    }
    if (f != NULL) {
        fclose(f);
    }
}

void proxy_run(const char *wsgsim, const char *wsgproxy, const char *out_dir, int rtt_n,
               const char *pin, proxy_result_t *r)
{
    char log_path[512], record[512], placement[96];
    server_t sim, px;
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-proxy.log", out_dir);
    if (!server_start_wsgsim(&sim, wsgsim, log_path, false)) {
        die("%s did not start (see %s)", wsgsim, log_path);
    }
    start_proxy(&px, &sim, wsgproxy, out_dir, record, sizeof(record));
    server_t *const both[2] = {&sim, &px};
    place_round_trips(both, 2, pin, placement, sizeof(placement));
    conn_t direct = {.fd = tcp_connect(sim.tcp_port)};
    conn_t proxied = {.fd = tcp_connect(px.tcp_port)};
    round_trips(&direct, PROXY_WARMUP, NULL);
    round_trips(&proxied, PROXY_WARMUP, NULL);
    samples_init(&r->direct, (size_t)rtt_n);
    samples_init(&r->proxied, (size_t)rtt_n);
    for (int b = 0; b < rtt_n / PROXY_BLOCK; b++) {
        round_trips(&direct, PROXY_BLOCK, &r->direct);
        round_trips(&proxied, PROXY_BLOCK, &r->proxied);
    }
    unplace_round_trips(both, 2);
    close(direct.fd);
    close(proxied.fd);
    r->pipelined = PIPELINED;
    r->answered = pipelined(px.tcp_port);
    server_stop(&px); /* SIGTERM: the record is complete */
    server_stop(&sim);
    count_record(record, &r->recorded_sent, &r->recorded_answered);
    r->expected_in_record = PROXY_WARMUP + (long)(rtt_n / PROXY_BLOCK) * PROXY_BLOCK + PIPELINED;
    samples_sort(&r->direct);
    samples_sort(&r->proxied);
}
