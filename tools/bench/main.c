/* SPDX-License-Identifier: BSD-3-Clause */
/* wsgbench: see bench.h and docs/benchmark.md.
 * usage: wsgbench [--wsgsim PATH] [--wsgproxy PATH] [--wsgsim-arg ARG]... [--out DIR] [--quick]
 * [--rtt N]
 *                 [--only SECTION] [--pin same|cross|none] [--firmware-sizes FILE]
 *        wsgbench --serve-echo      (the echo baseline alone, for callgrind)
 * --wsgsim-arg appends ARG to every wsgsim command line (e.g. --fingers=none).
 * --only runs one section (instr, web, streams, idle, subscribers, vtime, fleet,
 * scripts, scale, pace, timing, proxy, physics, rtt, load, autosend); the table then leaves
 * out the others. --wsgproxy names the recording proxy (default build/wsgproxy).
 * --firmware-sizes reads the Cortex-M image sizes `make bench` wrote. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "bench.h"
#include "report.h"

#define RTT_BLOCKS 20
#define RTT_WARMUP 1000
#define IDLE_CONNECTIONS 120
#define AUTOSEND_CLIENTS 16
#define SUBSCRIBERS 128
#define FLEET_DEVICES 1000
#define CELL_DEVICES 10000 /* --address-per-device: 127.1.0.1 .. 127.1.39.16 */
#define BUSY_SCRIPTS 32
#define CTL_STEP_MS 100
#define VTIME_BLOCKS 8 /* of RUN_UNTIL_DONE cycles, each for wsgsim and the responder */

static const int load_clients[LOAD_STEPS] = {1, 4, 16, 64};

typedef struct {
    const char *wsgsim;
    const char *wsgproxy;
    const char *out;
    int rtt_n;
    double idle_s;
    double load_s;
    double autosend_s;
    int cycles;
    double scale_s;             /* per SCALE value */
    int instr_seq_n;            /* callgrind: sequential POS? added over the base run */
    int instr_pipe_n;           /* callgrind: pipelined lines added over the base run */
    const char *only;           /* NULL: every section */
    const char *pin;            /* round trips: "same", "cross" or "none" */
    const char *firmware_sizes; /* NULL: not given */
} config_t;

static void quick(config_t *cfg)
{
    cfg->rtt_n = 4000;
    cfg->idle_s = 2.0;
    cfg->load_s = 0.5;
    cfg->autosend_s = 3.0;
    cfg->cycles = 100;
    cfg->scale_s = 0.5;
    cfg->instr_seq_n = 500;
    cfg->instr_pipe_n = 5000;
}

static void parse_args(int argc, char **argv, config_t *cfg)
{
    *cfg = (config_t){.wsgsim = "build/wsgsim",
                      .wsgproxy = "build/wsgproxy",
                      .out = "build/bench",
                      .rtt_n = 20000,
                      .idle_s = 10.0,
                      .load_s = 2.0,
                      .autosend_s = 10.0,
                      .cycles = 1000,
                      .scale_s = 2.0,
                      .instr_seq_n = 2000,
                      .instr_pipe_n = 20000,
                      .pin = "same"};
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--wsgsim") == 0 && i + 1 < argc) {
            cfg->wsgsim = argv[++i];
        } else if (strcmp(argv[i], "--wsgproxy") == 0 && i + 1 < argc) {
            cfg->wsgproxy = argv[++i];
        } else if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            cfg->out = argv[++i];
        } else if (strcmp(argv[i], "--rtt") == 0 && i + 1 < argc) {
            cfg->rtt_n = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--quick") == 0) {
            quick(cfg);
        } else if (strcmp(argv[i], "--pin") == 0 && i + 1 < argc) {
            cfg->pin = argv[++i];
        } else if (strcmp(argv[i], "--wsgsim-arg") == 0 && i + 1 < argc) {
            server_add_wsgsim_arg(argv[++i]);
        } else if (strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
            cfg->only = argv[++i];
        } else if (strcmp(argv[i], "--firmware-sizes") == 0 && i + 1 < argc) {
            cfg->firmware_sizes = argv[++i];
        } else {
            die("usage: wsgbench [--wsgsim PATH] [--wsgproxy PATH] [--wsgsim-arg ARG]... [--out "
                "DIR] [--quick] "
                "[--rtt N] [--only "
                "instr|web|streams|idle|subscribers|vtime|fleet|scripts|scale|pace|timing|"
                "proxy|physics|rtt|load|autosend] "
                "[--pin same|cross|none] [--firmware-sizes FILE]");
        }
    }
    if (cfg->rtt_n < RTT_BLOCKS) {
        die("--rtt must be at least %d", RTT_BLOCKS);
    }
}

static bool wanted(const config_t *cfg, const char *section)
{
    return cfg->only == NULL || strcmp(cfg->only, section) == 0;
}

/* Idle CPU and wake-ups ------------------------------------------------ */

#define STARTUP_SETTLE_US 1000000u

static void measure_idle(server_t *srv[2], double seconds, double pct[2], long wakeups[2])
{
    double cpu0[2];
    long sleeps0[2];
    for (int k = 0; k < 2; k++) {
        cpu0[k] = proc_cpu_us(srv[k]->pid);
        sleeps0[k] = proc_wakeups(srv[k]->pid);
    }
    double t0 = now_us();
    usleep((useconds_t)(seconds * 1e6));
    double wall = now_us() - t0;
    for (int k = 0; k < 2; k++) {
        pct[k] = 100.0 * (proc_cpu_us(srv[k]->pid) - cpu0[k]) / wall;
        wakeups[k] = proc_wakeups(srv[k]->pid) - sleeps0[k];
        if (cpu0[k] < 0 || sleeps0[k] < 0 || wakeups[k] < 0) {
            die("cannot read /proc of %s", srv[k]->name);
        }
    }
}

/* Idle connections: each sends one POS? (so it is accepted and served),
 * then stays silent. */
static void connect_idle(const server_t *srv, int fds[IDLE_CONNECTIONS])
{
    char line[256];
    for (int i = 0; i < IDLE_CONNECTIONS; i++) {
        conn_t c = {.fd = tcp_connect(srv->tcp_port)};
        if (!conn_send(&c, "POS?") || !conn_read_line(&c, line, sizeof(line), 5000)) {
            die("%s: idle connection %d not served", srv->name, i);
        }
        fds[i] = c.fd;
    }
}

static void run_idle(server_t *srv[2], const config_t *cfg, results_t *res)
{
    res->idle_s = cfg->idle_s;
    res->idle_connections = IDLE_CONNECTIONS;
    fprintf(stderr, "wsgbench: idle, no clients (%.0f s)\n", cfg->idle_s);
    /* after start-up the in-process finger bus settles for 500 ms of
     * simulated time (docs/finger-bus.md): measure the idle device after it */
    usleep(STARTUP_SETTLE_US);
    measure_idle(srv, cfg->idle_s, res->idle_pct, res->idle_wakeups);
    static int fds[2][IDLE_CONNECTIONS];
    for (int k = 0; k < 2; k++) {
        connect_idle(srv[k], fds[k]);
    }
    usleep(200000); /* the connections' own wake-ups are over */
    fprintf(stderr, "wsgbench: idle, %d idle connections (%.0f s)\n", IDLE_CONNECTIONS,
            cfg->idle_s);
    measure_idle(srv, cfg->idle_s, res->idle_conn_pct, res->idle_conn_wakeups);
    for (int k = 0; k < 2; k++) {
        res->rss_idle_kib[k] = proc_rss_kib(srv[k]->pid);
        for (int i = 0; i < IDLE_CONNECTIONS; i++) {
            close(fds[k][i]);
        }
    }
}

/* Round trips: alternating blocks so that both servers see the same noise. */

static void check_reply(const conn_t *c, const char *line, const server_t *srv)
{
    (void)c;
    const char *want = strcmp(srv->name, "echo") == 0 ? "POS?" : "POS=";
    if (strncmp(line, want, 4) != 0) {
        die("%s answered POS? with '%s'", srv->name, line);
    }
}

static void rtt_block_tcp(conn_t *c, const server_t *srv, int n, samples_t *out)
{
    for (int i = 0; i < n; i++) {
        double us;
        if (!rtt_tcp(c, "POS?", &us)) {
            die("%s: TCP round trip failed", srv->name);
        }
        if (out != NULL) {
            samples_add(out, us);
        }
    }
}

static void run_rtt_tcp(server_t *srv[2], const config_t *cfg, results_t *res)
{
    fprintf(stderr, "wsgbench: TCP round trips (N=%d each)\n", cfg->rtt_n);
    conn_t c[2];
    char line[256];
    for (int k = 0; k < 2; k++) {
        c[k].fd = tcp_connect(srv[k]->tcp_port);
        c[k].len = 0;
        if (!conn_send(&c[k], "POS?") || !conn_read_line(&c[k], line, sizeof(line), 2000)) {
            die("%s: no answer to POS?", srv[k]->name);
        }
        check_reply(&c[k], line, srv[k]);
        rtt_block_tcp(&c[k], srv[k], RTT_WARMUP, NULL);
        samples_init(&res->rtt_tcp[k], (size_t)cfg->rtt_n);
    }
    for (int b = 0; b < RTT_BLOCKS; b++) {
        for (int k = 0; k < 2; k++) {
            rtt_block_tcp(&c[k], srv[k], cfg->rtt_n / RTT_BLOCKS, &res->rtt_tcp[k]);
        }
    }
    for (int k = 0; k < 2; k++) {
        close(c[k].fd);
        samples_sort(&res->rtt_tcp[k]);
    }
}

/* wsgsim serves a UDP peer at most 1000 datagrams per second
 * (docs/behaviour.md) and drops the rest: the round trips keep below that
 * rate, with the same pacing for both servers, so a lost reply means lost. */
#define UDP_PACE_US 1100.0

static void rtt_block_udp(int fd, int n, samples_t *out, long *lost)
{
    double next_us = now_us();
    for (int i = 0; i < n; i++) {
        double wait_us = next_us - now_us();
        if (wait_us > 0) {
            usleep((useconds_t)wait_us);
        }
        next_us += UDP_PACE_US;
        double us;
        if (!rtt_udp(fd, "POS?", &us)) {
            (*lost)++;
        } else if (out != NULL) {
            samples_add(out, us);
        }
    }
}

static void run_rtt_udp(server_t *srv[2], const config_t *cfg, results_t *res)
{
    fprintf(stderr, "wsgbench: UDP round trips (N=%d each, one per %.1f ms)\n", cfg->rtt_n,
            UDP_PACE_US / 1000.0);
    int fd[2];
    long warm_lost = 0;
    for (int k = 0; k < 2; k++) {
        fd[k] = udp_connect(srv[k]->udp_port);
        rtt_block_udp(fd[k], RTT_WARMUP, NULL, &warm_lost);
        samples_init(&res->rtt_udp[k], (size_t)cfg->rtt_n);
        res->udp_lost[k] = 0;
    }
    for (int b = 0; b < RTT_BLOCKS; b++) {
        for (int k = 0; k < 2; k++) {
            rtt_block_udp(fd[k], cfg->rtt_n / RTT_BLOCKS, &res->rtt_udp[k], &res->udp_lost[k]);
        }
    }
    for (int k = 0; k < 2; k++) {
        close(fd[k]);
        samples_sort(&res->rtt_udp[k]);
    }
}

static void run_load(server_t *srv[2], const config_t *cfg, results_t *res)
{
    for (int i = 0; i < LOAD_STEPS; i++) {
        res->load_clients[i] = load_clients[i];
        for (int k = 0; k < 2; k++) {
            fprintf(stderr, "wsgbench: pipelined load, %s, %d clients (%.1f s)\n", srv[k]->name,
                    load_clients[i], cfg->load_s);
            res->load_rps[i][k] = throughput(srv[k]->tcp_port, load_clients[i], cfg->load_s);
        }
    }
}

static void run_autosend(server_t *srv[2], const config_t *cfg, results_t *res)
{
    for (int k = 0; k < 2; k++) {
        fprintf(stderr, "wsgbench: AUTOSEND %d clients x 10 ms, %s (%.0f s)\n", AUTOSEND_CLIENTS,
                srv[k]->name, cfg->autosend_s);
        autosend_run(srv[k]->tcp_port, AUTOSEND_CLIENTS, cfg->autosend_s, &res->autosend[k]);
    }
    res->autosend_clients = AUTOSEND_CLIENTS;
}

/* Whether the control channel lists RUN_UNTIL_DONE (older builds do not). */
static bool has_run_until_done(const server_t *srv)
{
    conn_t ctl = {.fd = tcp_connect(srv->ctl_port)};
    char reply[4096] = "";
    bool listed = conn_send(&ctl, "HELP?") && conn_read_line(&ctl, reply, sizeof(reply), 5000) &&
                  strstr(reply, "RUN_UNTIL_DONE") != NULL;
    close(ctl.fd);
    return listed;
}

/* wsgsim's RUN_UNTIL_DONE cycles in blocks that alternate with the same
 * client's blocks against the zero-work responder, in the order ABBA (so
 * that a machine whose speed drifts favours neither), placed on the CPUs as
 * the round trips are (--pin: a cross-CPU wake-up swamps the difference).
 * A first block, not counted, warms wsgsim up and tells the responder how
 * much simulated time a command takes there. */
static void run_until_done_beside_floor(server_t *wsgsim, const config_t *cfg, results_t *res)
{
    vtime_result_t *w = &res->vtime_run_until;
    vtime_result_t *f = &res->vtime_floor;
    int block = cfg->cycles / VTIME_BLOCKS > 0 ? cfg->cycles / VTIME_BLOCKS : 1;
    vtime_session_t at_wsgsim;
    vtime_session_t at_floor;
    server_t floor_srv;
    vtime_result_t warm_up = {0};
    vtime_session_open(&at_wsgsim, wsgsim);
    vtime_session_run(&at_wsgsim, block, 0, &warm_up);
    double ms_per_command =
        warm_up.cycles_done > 0 ? warm_up.virtual_s * 1e3 / (4.0 * warm_up.cycles_done) : 0;
    if (!server_start_responder(&floor_srv, ms_per_command)) {
        die("cannot start the zero-work responder");
    }
    server_t *servers[2] = {wsgsim, &floor_srv};
    place_round_trips(servers, 2, cfg->pin, res->placement, sizeof(res->placement));
    vtime_session_open(&at_floor, &floor_srv);
    memset(w, 0, sizeof(*w));
    memset(f, 0, sizeof(*f));
    for (int b = 0; b < 2 * VTIME_BLOCKS; b++) {
        bool wsgsim_turn = ((b + 1) / 2) % 2 == 0; /* W R R W W R R W ... */
        vtime_session_run(wsgsim_turn ? &at_wsgsim : &at_floor, block, 0, wsgsim_turn ? w : f);
    }
    unplace_round_trips(servers, 2);
    vtime_session_close(&at_wsgsim);
    vtime_session_close(&at_floor);
    server_stop(&floor_srv);
}

/* Through a paused wsgsim when it has the control channel. */
static void run_vtime_ctl(const config_t *cfg, results_t *res)
{
    char log_path[512];
    server_t paused;
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-paused.log", cfg->out);
    if (!server_start_wsgsim(&paused, cfg->wsgsim, log_path, true) || paused.ctl_port == 0) {
        fprintf(stderr, "wsgbench: %s has no control channel: skipping the stepped run\n",
                cfg->wsgsim);
        server_stop(&paused);
        return;
    }
    int cycles = cfg->cycles / 10;
    fprintf(stderr, "wsgbench: virtual time through the control channel, %d cycles, STEP(%d)\n",
            cycles, CTL_STEP_MS);
    vtime_ctl_run(&paused, cycles, CTL_STEP_MS, &res->vtime_ctl);
    res->vtime_ctl_step_ms = CTL_STEP_MS;
    server_stop(&paused);
    if (!server_start_wsgsim(&paused, cfg->wsgsim, log_path, true) || paused.ctl_port == 0) {
        die("%s did not start again with a control channel (see %s)", cfg->wsgsim, log_path);
    }
    if (has_run_until_done(&paused)) {
        fprintf(stderr,
                "wsgbench: virtual time through the control channel, %d cycles, "
                "RUN_UNTIL_DONE, beside a zero-work responder\n",
                cfg->cycles);
        run_until_done_beside_floor(&paused, cfg, res);
    }
    server_stop(&paused);
}

/* The scaled clock's rate, on a server of its own (resumed from paused). */
static void run_scale(const config_t *cfg, results_t *res)
{
    static const double scales[SCALE_STEPS] = {1.0, 10.0, 0.5};
    char log_path[512];
    server_t srv;
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-scale.log", cfg->out);
    if (!server_start_wsgsim(&srv, cfg->wsgsim, log_path, true) || srv.ctl_port == 0) {
        die("%s did not start with a control channel (see %s)", cfg->wsgsim, log_path);
    }
    fprintf(stderr, "wsgbench: scaled clock at 1x, 10x, 0.5x (%.1f s each)\n", cfg->scale_s);
    memcpy(res->scale.scale, scales, sizeof(scales));
    scale_run(&srv, cfg->scale_s, &res->scale);
    server_stop(&srv);
}

/* A MOVE's wall time, quiet and under a POS? flood, on a server of its own
 * without fingers (their bus would step the device every 10 ms anyway). */
static void run_pace(const config_t *cfg, results_t *res)
{
    const char *argv[48];
    int n = wsgsim_argv(argv, 44, cfg->wsgsim, false);
    argv[n++] = "--fingers";
    argv[n++] = "none,none";
    argv[n] = NULL;
    char log_path[512];
    server_t srv;
    snprintf(log_path, sizeof(log_path), "%s/wsgsim-pace.log", cfg->out);
    if (!server_start_cmd(&srv, "wsgsim", argv, log_path, 30.0)) {
        die("%s did not start (see %s)", cfg->wsgsim, log_path);
    }
    fprintf(stderr, "wsgbench: a MOVE, quiet and under a POS? flood\n");
    pace_run(&srv, &res->pace);
    server_stop(&srv);
}

/* The processor's model as /proc/cpuinfo names it ("" where it does not):
 * hosts that look alike can differ in how their figures swing
 * (docs/benchmark.md). */
static void cpu_model(char *out, size_t size)
{
    char line[256];
    FILE *f = fopen("/proc/cpuinfo", "r");
    out[0] = '\0';
    while (f != NULL && fgets(line, sizeof(line), f) != NULL) {
        const char *colon = strchr(line, ':');
        if (strncmp(line, "model name", 10) == 0 && colon != NULL) {
            const char *name = colon + 1 + strspn(colon + 1, " \t");
            snprintf(out, size, "%.*s", (int)strcspn(name, "\n"), name);
            break;
        }
    }
    if (f != NULL) {
        fclose(f);
    }
}

static void describe_machine(results_t *res)
{
    struct utsname u;
    char model[128];
    uname(&u);
    cpu_model(model, sizeof(model));
    snprintf(res->machine, sizeof(res->machine), "%s %s %s, %ld CPUs%s%s", u.sysname, u.release,
             u.machine, sysconf(_SC_NPROCESSORS_ONLN), model[0] != '\0' ? ", " : "", model);
}

/* The image sizes `make bench` wrote: "NAME FLASH FLASH_MAX RAM RAM_MAX". */
static void read_firmware_sizes(const char *path, results_t *res)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        die("cannot read %s", path);
    }
    firmware_size_t fw;
    while (res->firmware_count < FIRMWARE_IMAGES_MAX &&
           fscanf(f, "%31s %ld %ld %ld %ld", fw.name, &fw.flash, &fw.flash_max, &fw.ram,
                  &fw.ram_max) == 5) {
        res->firmware[res->firmware_count++] = fw;
    }
    fclose(f);
    if (res->firmware_count == 0) {
        die("no image sizes in %s", path);
    }
    res->firmware_read = true;
}

/* Sections that start servers of their own (under callgrind, paused, a
 * fleet), before the pair of servers the others share. */
static void run_own_server_sections(const config_t *cfg, results_t *res)
{
    char path[512];
    if (wanted(cfg, "instr")) {
        char self[512];
        ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
        if (n <= 0) {
            die("cannot find my own executable");
        }
        self[n] = '\0';
        instr_run(cfg->wsgsim, self, cfg->out, cfg->instr_seq_n, cfg->instr_pipe_n, &res->instr);
    }
    if (wanted(cfg, "web")) {
        web_run(cfg->wsgsim, cfg->out, cfg->instr_seq_n / 10, cfg->instr_seq_n / 20, &res->web);
    }
    if (wanted(cfg, "streams")) {
        streams_run(cfg->wsgsim, cfg->out, cfg->idle_s / 2.0, cfg->rtt_n / 4, cfg->pin,
                    &res->streams);
    }
    if (wanted(cfg, "vtime")) {
        fprintf(stderr, "wsgbench: virtual time, %d HOME/MOVE/GRIP/RELEASE cycles\n", cfg->cycles);
        vtime_run(cfg->cycles, &res->vtime);
        run_vtime_ctl(cfg, res);
    }
    if (wanted(cfg, "subscribers")) {
        fprintf(stderr, "wsgbench: AUTOSEND %d subscribers x 10 ms, one phase (%.0f s)\n",
                SUBSCRIBERS, cfg->autosend_s);
        snprintf(path, sizeof(path), "%s/wsgsim-subscribers.log", cfg->out);
        subscribers_run(cfg->wsgsim, path, SUBSCRIBERS, cfg->autosend_s, &res->subscribers);
    }
    if (wanted(cfg, "fleet")) {
        fprintf(stderr, "wsgbench: fleet of %d devices\n", FLEET_DEVICES);
        fleet_run(cfg->wsgsim, cfg->out, FLEET_DEVICES, cfg->idle_s, cfg->pin, &res->fleet);
        fprintf(stderr, "wsgbench: a cell of %d addresses\n", CELL_DEVICES);
        fleet_cell_run(cfg->wsgsim, cfg->out, CELL_DEVICES, cfg->idle_s, &res->cell);
    }
    if (wanted(cfg, "scripts")) {
        fprintf(stderr, "wsgbench: device 0 beside %d busy scripts\n", BUSY_SCRIPTS);
        scripts_run(cfg->wsgsim, cfg->out, BUSY_SCRIPTS, &res->scripts);
    }
    if (wanted(cfg, "scale")) {
        run_scale(cfg, res);
    }
    if (wanted(cfg, "timing")) {
        fprintf(stderr, "wsgbench: 1,000 paused-clock requests under wsg50 and ideal\n");
        timing_run(cfg->wsgsim, cfg->out, &res->timing);
    }
    if (wanted(cfg, "pace")) {
        run_pace(cfg, res);
    }
    if (wanted(cfg, "proxy")) {
        fprintf(stderr, "wsgbench: the recording proxy, %d POS? each way\n", cfg->rtt_n / 2);
        proxy_run(cfg->wsgsim, cfg->wsgproxy, cfg->out, cfg->rtt_n / 2, cfg->pin, &res->proxy);
    }
    if (wanted(cfg, "physics")) {
        fprintf(stderr, "wsgbench: the default physics scene, paused and running\n");
        physics_run(cfg->wsgsim, cfg->out, &res->physics);
    }
}

static void run_shared_server_sections(const config_t *cfg, results_t *res)
{
    char log_path[512];
    snprintf(log_path, sizeof(log_path), "%s/wsgsim.log", cfg->out);
    server_t wsg;
    server_t echo;
    if (!server_start_wsgsim(&wsg, cfg->wsgsim, log_path, false)) {
        die("%s did not start (see %s)", cfg->wsgsim, log_path);
    }
    if (!server_start_echo(&echo)) {
        die("the echo server did not start");
    }
    server_t *srv[2] = {&wsg, &echo};
    fprintf(stderr, "wsgbench: wsgsim pid %d, echo pid %d\n", (int)wsg.pid, (int)echo.pid);
    if (wanted(cfg, "idle")) {
        run_idle(srv, cfg, res);
    }
    if (wanted(cfg, "rtt")) {
        place_round_trips(srv, 2, cfg->pin, res->placement, sizeof(res->placement));
        fprintf(stderr, "wsgbench: round trips with %s\n", res->placement);
        run_rtt_tcp(srv, cfg, res);
        run_rtt_udp(srv, cfg, res);
        unplace_round_trips(srv, 2);
    }
    if (wanted(cfg, "load")) {
        run_load(srv, cfg, res);
    }
    if (wanted(cfg, "autosend")) {
        run_autosend(srv, cfg, res);
    }
    res->rss_peak_kib[0] = proc_hwm_kib(wsg.pid);
    res->rss_peak_kib[1] = proc_hwm_kib(echo.pid);
    server_stop(&wsg);
    server_stop(&echo);
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "--serve-echo") == 0) {
        echo_server_main();
    }
    config_t cfg;
    parse_args(argc, argv, &cfg);
    if (mkdir(cfg.out, 0755) != 0 && errno != EEXIST) {
        die("cannot create %s", cfg.out);
    }
    static results_t res;
    describe_machine(&res);
    if (cfg.firmware_sizes != NULL) {
        read_firmware_sizes(cfg.firmware_sizes, &res);
    }
    res.firmware_expected = cfg.only == NULL;
    run_own_server_sections(&cfg, &res);
    if (wanted(&cfg, "idle") || wanted(&cfg, "rtt") || wanted(&cfg, "load") ||
        wanted(&cfg, "autosend")) {
        run_shared_server_sections(&cfg, &res);
    }
    report_print(&res, stdout);
    report_write_json(&res, cfg.out);
    report_plot(&res, cfg.out);
    return 0;
}
