/* wsgbench: see bench.h and docs/benchmark.md.
 * usage: wsgbench [--wsgsim PATH] [--wsgsim-arg ARG]... [--out DIR] [--quick] [--rtt N]
 *                 [--only SECTION]
 * --wsgsim-arg appends ARG to every wsgsim command line (e.g. --fingers=none).
 * --only runs one section (vtime, scale, idle, rtt, load, autosend) for profiling;
 * the table then shows zeros for the others. */
#include <errno.h>
#include <sched.h>
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
#define IDLE_CONNECTIONS 8
#define AUTOSEND_CLIENTS 16
#define CTL_STEP_MS 100

static const int load_clients[LOAD_STEPS] = {1, 4, 16, 64};

typedef struct {
    const char *wsgsim;
    const char *out;
    int rtt_n;
    double idle_s;
    double load_s;
    double autosend_s;
    int cycles;
    double scale_s;   /* per SCALE value */
    const char *only; /* NULL: every section */
    const char *pin;  /* round trips: "same", "cross" or "none" */
} config_t;

static void parse_args(int argc, char **argv, config_t *cfg)
{
    *cfg =
        (config_t){"build/wsgsim", "build/bench", 20000, 10.0, 2.0, 10.0, 1000, 2.0, NULL, "same"};
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--wsgsim") == 0 && i + 1 < argc) {
            cfg->wsgsim = argv[++i];
        } else if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            cfg->out = argv[++i];
        } else if (strcmp(argv[i], "--rtt") == 0 && i + 1 < argc) {
            cfg->rtt_n = atoi(argv[++i]);
        } else if (strcmp(argv[i], "--quick") == 0) {
            *cfg = (config_t){cfg->wsgsim, cfg->out, 4000, 2.0,       0.5,
                              3.0,         100,      0.5,  cfg->only, cfg->pin};
        } else if (strcmp(argv[i], "--pin") == 0 && i + 1 < argc) {
            cfg->pin = argv[++i];
        } else if (strcmp(argv[i], "--wsgsim-arg") == 0 && i + 1 < argc) {
            server_add_wsgsim_arg(argv[++i]);
        } else if (strcmp(argv[i], "--only") == 0 && i + 1 < argc) {
            cfg->only = argv[++i];
        } else {
            die("usage: wsgbench [--wsgsim PATH] [--wsgsim-arg ARG]... [--out DIR] [--quick] "
                "[--rtt N] [--only vtime|scale|idle|rtt|load|autosend] [--pin same|cross|none]");
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

/* Idle CPU ------------------------------------------------------------- */

static void measure_idle(server_t *srv[2], double seconds, double pct[2], long wakeups[2])
{
    double cpu0[2];
    long ctx0[2];
    for (int k = 0; k < 2; k++) {
        cpu0[k] = proc_cpu_us(srv[k]->pid);
        ctx0[k] = proc_ctx_switches(srv[k]->pid);
    }
    double t0 = now_us();
    usleep((useconds_t)(seconds * 1e6));
    double wall = now_us() - t0;
    for (int k = 0; k < 2; k++) {
        pct[k] = 100.0 * (proc_cpu_us(srv[k]->pid) - cpu0[k]) / wall;
        wakeups[k] = proc_ctx_switches(srv[k]->pid) - ctx0[k];
    }
}

static void run_idle(server_t *srv[2], const config_t *cfg, results_t *res)
{
    fprintf(stderr, "wsgbench: idle CPU, no clients (%.0f s)\n", cfg->idle_s);
    measure_idle(srv, cfg->idle_s, res->idle_pct, res->idle_wakeups);
    int fds[2][IDLE_CONNECTIONS];
    for (int k = 0; k < 2; k++) {
        for (int i = 0; i < IDLE_CONNECTIONS; i++) {
            fds[k][i] = tcp_connect(srv[k]->tcp_port);
        }
    }
    fprintf(stderr, "wsgbench: idle CPU, %d idle connections (%.0f s)\n", IDLE_CONNECTIONS,
            cfg->idle_s);
    measure_idle(srv, cfg->idle_s, res->idle_conn_pct, res->idle_conn_wakeups);
    for (int k = 0; k < 2; k++) {
        res->rss_idle_kib[k] = proc_rss_kib(srv[k]->pid);
        for (int i = 0; i < IDLE_CONNECTIONS; i++) {
            close(fds[k][i]);
        }
    }
}

/* CPU placement for the round trips. Unpinned, a sequential round trip
 * costs one or two cross-CPU wakeups or none, depending on where the
 * scheduler happens to put each server (on a VM about 40 us each way), which
 * swamps the difference between the servers. "same": the client and both
 * servers on the first CPU; "cross": the client on the first, the servers
 * on the second; "none": as the scheduler likes. */
static void set_cpu(pid_t pid, int cpu)
{
    cpu_set_t set;
    CPU_ZERO(&set);
    if (cpu < 0) {
        for (int i = 0; i < CPU_SETSIZE; i++) {
            CPU_SET(i, &set);
        }
    } else {
        CPU_SET(cpu, &set);
    }
    sched_setaffinity(pid, sizeof(set), &set);
}

static int online_cpu(int nth)
{
    cpu_set_t set;
    sched_getaffinity(0, sizeof(set), &set);
    for (int i = 0, seen = 0; i < CPU_SETSIZE; i++) {
        if (CPU_ISSET(i, &set) && seen++ == nth) {
            return i;
        }
    }
    return -1;
}

static void pin_round_trips(server_t *srv[2], const char *mode, results_t *res)
{
    int client = online_cpu(0);
    int server = strcmp(mode, "cross") == 0 ? online_cpu(1) : client;
    if (strcmp(mode, "none") == 0 || client < 0 || server < 0) {
        snprintf(res->placement, sizeof(res->placement), "unpinned");
        return;
    }
    set_cpu(0, client);
    for (int k = 0; k < 2; k++) {
        set_cpu(srv[k]->pid, server);
    }
    snprintf(res->placement, sizeof(res->placement), "client on CPU %d, servers on CPU %d", client,
             server);
}

static void unpin(server_t *srv[2])
{
    set_cpu(0, -1);
    for (int k = 0; k < 2; k++) {
        set_cpu(srv[k]->pid, -1);
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

static void rtt_block_udp(int fd, int n, samples_t *out, long *lost)
{
    for (int i = 0; i < n; i++) {
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
    fprintf(stderr, "wsgbench: UDP round trips (N=%d each)\n", cfg->rtt_n);
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

static void describe_machine(results_t *res)
{
    struct utsname u;
    uname(&u);
    snprintf(res->machine, sizeof(res->machine), "%s %s %s, %ld CPUs", u.sysname, u.release,
             u.machine, sysconf(_SC_NPROCESSORS_ONLN));
}

int main(int argc, char **argv)
{
    config_t cfg;
    parse_args(argc, argv, &cfg);
    if (mkdir(cfg.out, 0755) != 0 && errno != EEXIST) {
        die("cannot create %s", cfg.out);
    }
    static results_t res;
    describe_machine(&res);
    char log_path[512];
    snprintf(log_path, sizeof(log_path), "%s/wsgsim.log", cfg.out);
    if (wanted(&cfg, "vtime")) {
        fprintf(stderr, "wsgbench: virtual time, %d HOME/MOVE/GRIP/RELEASE cycles\n", cfg.cycles);
        vtime_run(cfg.cycles, &res.vtime);
    }
    server_t wsg;
    server_t echo;
    if (wanted(&cfg, "vtime")) {
        run_vtime_ctl(&cfg, &res);
    }
    if (wanted(&cfg, "scale")) {
        run_scale(&cfg, &res);
    }
    if (!server_start_wsgsim(&wsg, cfg.wsgsim, log_path, false)) {
        die("%s did not start (see %s)", cfg.wsgsim, log_path);
    }
    if (!server_start_echo(&echo)) {
        die("the echo server did not start");
    }
    server_t *srv[2] = {&wsg, &echo};
    fprintf(stderr, "wsgbench: wsgsim pid %d, echo pid %d\n", (int)wsg.pid, (int)echo.pid);
    if (wanted(&cfg, "idle")) {
        run_idle(srv, &cfg, &res);
    }
    if (wanted(&cfg, "rtt")) {
        pin_round_trips(srv, cfg.pin, &res);
        fprintf(stderr, "wsgbench: round trips with %s\n", res.placement);
        run_rtt_tcp(srv, &cfg, &res);
        run_rtt_udp(srv, &cfg, &res);
        unpin(srv);
    }
    if (wanted(&cfg, "load")) {
        run_load(srv, &cfg, &res);
    }
    if (wanted(&cfg, "autosend")) {
        run_autosend(srv, &cfg, &res);
    }
    res.rss_peak_kib[0] = proc_hwm_kib(wsg.pid);
    res.rss_peak_kib[1] = proc_hwm_kib(echo.pid);
    server_stop(&wsg);
    server_stop(&echo);
    report_print(&res, stdout);
    report_write_json(&res, cfg.out);
    report_plot(&res, cfg.out);
    return 0;
}
