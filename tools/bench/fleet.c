/* SPDX-License-Identifier: BSD-3-Clause */
/* Many devices in one process (`--devices N`): start time, idle
 * wake-ups, memory per idle device and POS? round trips against a single
 * device. Device i serves TCP and UDP on base port + i. Until wsgsim has the
 * option, nothing is measured and the report says so. */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bench.h"

#define RTT_SAMPLES 2000
#define START_LIMIT_S 60.0
#define PORT_FIRST 20000
#define PORT_LAST 60000

static bool has_devices_option(const char *wsgsim)
{
    char cmd[600];
    snprintf(cmd, sizeof(cmd), "'%s' --help 2>&1", wsgsim);
    FILE *p = popen(cmd, "r");
    if (p == NULL) {
        die("cannot run %s --help", wsgsim);
    }
    char line[512];
    bool found = false;
    while (fgets(line, sizeof(line), p) != NULL) {
        found = found || strstr(line, "--devices") != NULL;
    }
    if (pclose(p) != 0) {
        die("%s --help failed", wsgsim);
    }
    return found;
}

static bool port_free(int type, int port)
{
    int fd = socket(AF_INET, type, 0);
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bool ok = fd >= 0 && bind(fd, (struct sockaddr *)&sa, sizeof(sa)) == 0;
    if (fd >= 0) {
        close(fd);
    }
    return ok;
}

int free_port_range(int count)
{
    for (int base = PORT_FIRST; base + count <= PORT_LAST; base += count) {
        int i = 0;
        while (i < count && port_free(SOCK_STREAM, base + i) && port_free(SOCK_DGRAM, base + i)) {
            i++;
        }
        if (i == count) {
            return base;
        }
    }
    die("no %d free loopback ports in a row", count);
}

static bool start_fleet(server_t *srv, const char *wsgsim, const char *out_dir, int devices,
                        int base)
{
    char count[16];
    char port[16];
    char log_path[512];
    snprintf(count, sizeof(count), "%d", devices);
    snprintf(port, sizeof(port), "%d", base);
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-fleet-%d.log", out_dir, devices);
    const char *argv[48];
    int n = wsgsim_argv(argv, 44, wsgsim, false);
    for (int i = 0; i < n; i++) { /* fixed ports: device i on base + i */
        if (strcmp(argv[i], "--tcp-port") == 0 || strcmp(argv[i], "--udp-port") == 0) {
            argv[i + 1] = port;
        }
    }
    argv[n++] = "--devices";
    argv[n++] = count;
    argv[n] = NULL;
    return server_start_cmd(srv, "wsgsim", argv, log_path, START_LIMIT_S);
}

static double rtt_p50(int port)
{
    conn_t c = {.fd = tcp_connect(port)};
    samples_t s;
    samples_init(&s, RTT_SAMPLES);
    for (int i = 0; i < RTT_SAMPLES; i++) {
        double us;
        if (!rtt_tcp(&c, "POS?", &us)) {
            die("fleet: no answer to POS? on port %d", port);
        }
        samples_add(&s, us);
    }
    close(c.fd);
    samples_sort(&s);
    double p50 = samples_quantile(&s, 0.5);
    samples_free(&s);
    return p50;
}

/* The start-up's own work (the devices' first steps and timers) goes on for
 * a moment after the ready line: the window opens once it has settled. */
#define FLEET_SETTLE_S 2.0
/* A cell (--address-per-device): device i on 127.1.0.1 + i, serial base + i. */
#define CELL_FIRST_ADDRESS 0x7f010001u
#define CELL_FIRST_SERIAL 12345678u

static long settled_rss(const server_t *srv, double idle_s, double *wakeups_per_s)
{
    usleep((useconds_t)(FLEET_SETTLE_S * 1e6));
    long before = proc_wakeups(srv->pid);
    double t0 = now_us();
    usleep((useconds_t)(idle_s * 1e6));
    *wakeups_per_s = (double)(proc_wakeups(srv->pid) - before) / ((now_us() - t0) / 1e6);
    return proc_rss_kib(srv->pid);
}

/* POS? p50 on each sampled device (its worst), with the client and the
 * server placed as the round-trip rows are. */
static double worst_rtt_p50(server_t *srv, const char *pin, int base, const int *sampled, int n)
{
    char placement[96];
    server_t *servers[1] = {srv};
    double worst = 0;
    place_round_trips(servers, 1, pin, placement, sizeof(placement));
    for (int i = 0; i < n; i++) {
        double p50 = rtt_p50(base + sampled[i]);
        worst = p50 > worst ? p50 : worst;
    }
    unplace_round_trips(servers, 1);
    return worst;
}

void fleet_run(const char *wsgsim, const char *out_dir, int devices, double idle_s, const char *pin,
               fleet_result_t *r)
{
    memset(r, 0, sizeof(*r));
    r->devices = devices;
    r->available = has_devices_option(wsgsim);
    if (!r->available) {
        return;
    }
    server_t one;
    server_t fleet;
    double unused;
    int base = free_port_range(devices);
    if (!start_fleet(&one, wsgsim, out_dir, 1, base)) {
        die("%s --devices 1 did not start", wsgsim);
    }
    long rss_one = settled_rss(&one, idle_s, &unused);
    const int first[1] = {0};
    r->single_rtt_p50_us = worst_rtt_p50(&one, pin, base, first, 1);
    server_stop(&one);
    double t0 = now_us();
    if (!start_fleet(&fleet, wsgsim, out_dir, devices, base)) {
        die("%s --devices %d did not start", wsgsim, devices);
    }
    r->start_s = (now_us() - t0) / 1e6;
    long rss_fleet = settled_rss(&fleet, idle_s, &r->idle_wakeups_per_s);
    r->kib_per_device = (double)(rss_fleet - rss_one) / (devices - 1);
    const int sampled[3] = {0, devices / 2, devices - 1};
    r->rtt_p50_us = worst_rtt_p50(&fleet, pin, base, sampled, 3);
    server_stop(&fleet);
}

/* SN? to device i of a cell from 127.1.0.1 at port: its serial (base + i)
 * must come back. */
static bool cell_device_answers(int i, int port)
{
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    sa.sin_addr.s_addr = htonl(CELL_FIRST_ADDRESS + (uint32_t)i);
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    char expected[32];
    char reply[64] = "";
    snprintf(expected, sizeof(expected), "SN=%u\n", CELL_FIRST_SERIAL + (unsigned)i);
    struct timeval limit = {.tv_sec = 10};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof(limit));
    bool ok = fd >= 0 && connect(fd, (const struct sockaddr *)&sa, sizeof(sa)) == 0 &&
              send(fd, "SN?\n", 4, MSG_NOSIGNAL) == 4 && recv(fd, reply, sizeof(reply) - 1, 0) > 0;
    if (fd >= 0) {
        close(fd);
    }
    return ok && strcmp(reply, expected) == 0;
}

void fleet_cell_run(const char *wsgsim, const char *out_dir, int devices, double idle_s,
                    fleet_cell_result_t *r)
{
    memset(r, 0, sizeof(*r));
    char count[16];
    char log_path[512];
    snprintf(count, sizeof(count), "%d", devices);
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-cell-%d.log", out_dir, devices);
    const char *argv[48];
    int n = wsgsim_argv(argv, 44, wsgsim, false);
    for (int i = 0; i < n; i++) {
        if (strcmp(argv[i], "--bind") == 0) {
            argv[i + 1] = "127.1.0.1";
        }
    }
    argv[n++] = "--devices";
    argv[n++] = count;
    argv[n++] = "--address-per-device";
    argv[n] = NULL;
    server_t cell;
    double t0 = now_us();
    if (!server_start_cmd(&cell, "wsgsim", argv, log_path, START_LIMIT_S)) {
        die("%s --devices %d --address-per-device did not start", wsgsim, devices);
    }
    r->devices = devices;
    r->start_s = (now_us() - t0) / 1e6;
    r->last_answers = cell_device_answers(devices - 1, cell.tcp_port);
    settled_rss(&cell, idle_s, &r->idle_wakeups_per_s);
    r->peak_rss_kib = proc_hwm_kib(cell.pid);
    server_stop(&cell);
}
