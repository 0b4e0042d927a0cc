/* SPDX-License-Identifier: BSD-3-Clause */
/* wsgbench: measures build/wsgsim side by side with a minimal C line-echo
 * server (the loopback limit of this machine) and the core's virtual-time
 * speed in-process. libc only. */
#ifndef BENCH_H
#define BENCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#define BENCH_PERIOD_MS 10

/* A server under test: wsgsim or the echo baseline, in a child process. */
typedef struct {
    const char *name;
    pid_t pid;
    int tcp_port;
    int udp_port;
    int ctl_port; /* simulation control channel, 0: none */
} server_t;

/* Samples in microseconds. */
typedef struct {
    double *v;
    size_t n;
    size_t cap;
} samples_t;

void samples_init(samples_t *s, size_t cap);
void samples_free(samples_t *s);
void samples_add(samples_t *s, double us);
void samples_sort(samples_t *s);
/* q in [0,1] of sorted samples; 0 when empty. */
double samples_quantile(const samples_t *s, double q);
double samples_max(const samples_t *s);

double now_us(void);
void die(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));
/* An epoll set watching two descriptors for input; dies naming `who`. */
int epoll_for_two(int fd_a, int fd_b, const char *who);

/* proc.c */
#define WSGSIM_EXTRA_ARGS_MAX 8
/* Appends an argument to every wsgsim the benchmark starts. */
void server_add_wsgsim_arg(const char *arg);
/* wsgsim's command line (NULL-terminated in argv, at most cap entries);
 * returns the count. paused: --start-paused with a control channel and a
 * 30 mm part; otherwise a free-running server. */
int wsgsim_argv(const char **argv, int cap, const char *binary, bool paused);
bool server_start_wsgsim(server_t *srv, const char *binary, const char *log_path, bool paused);
/* Any command that logs "ready: tcp HOST:PORT, udp HOST:PORT[, control
 * HOST:PORT]" to stderr (wsgsim, `wsgbench --serve-echo`, either under
 * valgrind); stderr goes to log_path. */
bool server_start_cmd(server_t *srv, const char *name, const char *const *argv,
                      const char *log_path, double timeout_s);
bool server_start_echo(server_t *srv);
/* The zero-work responder (responder.c) on free loopback ports: GCL on
 * tcp_port, the control channel on ctl_port. */
bool server_start_responder(server_t *srv, double ms_per_command);
void server_stop(server_t *srv);
/* SIGTERM, then SIGKILL after `seconds`; true when it ended by itself. */
bool server_stop_within(server_t *srv, double seconds);
/* Pins this process (the client) and the n servers for round trips by
 * mode ("same", "cross" or "none", see proc.c), describing it in
 * placement; unplace_round_trips() lets them run anywhere again. */
void place_round_trips(server_t *const *srv, int n, const char *mode, char *placement, size_t cap);
void unplace_round_trips(server_t *const *srv, int n);
/* A process that stands in for other machines' clients (the event streams'
 * reader), placed for the round trips of `mode` on the CPU the servers are
 * not on, so that it does not take their CPU; "none": anywhere. Call it
 * before place_round_trips(), which narrows this process's own CPUs (the
 * ones both read). */
void place_apart(pid_t pid, const char *mode);
/* Kills every server still running (die() calls it). */
void server_kill_all(void);
/* CPU time (user+system) of a process in microseconds. */
double proc_cpu_us(pid_t pid);
/* VmRSS / VmHWM in KiB; -1 when unknown. */
long proc_rss_kib(pid_t pid);
long proc_hwm_kib(pid_t pid);
long proc_ctx_switches(pid_t pid);
/* Times the process went to sleep (voluntary context switches): each
 * sleep ends in one wake-up. */
long proc_wakeups(pid_t pid);

/* echo.c: serves until SIGTERM; never returns. */
void echo_server_run(int tcp_fd, int udp_fd) __attribute__((noreturn));
/* `wsgbench --serve-echo`: the echo server on free loopback ports as a
 * program of its own (to run it under callgrind); logs its ready line. */
void echo_server_main(void) __attribute__((noreturn));
/* responder.c: serves until SIGTERM; never returns. */
void responder_server_run(int gcl_listen_fd, int ctl_listen_fd, double ms_per_command)
    __attribute__((noreturn));

/* client.c */
typedef struct {
    int fd;
    char buf[8192];
    size_t len;
} conn_t;

int tcp_connect(int port);
/* As tcp_connect(), but -1 instead of dying when nothing accepts. */
int try_tcp_connect(int port);
int udp_connect(int port);
/* Sends a line (adds '\n') and reads one reply line into out. */
bool conn_send(conn_t *c, const char *line);
bool conn_read_line(conn_t *c, char *out, size_t cap, int timeout_ms);
bool rtt_tcp(conn_t *c, const char *req, double *us);
bool rtt_udp(int fd, const char *req, double *us);
/* Pipelined replies per second over `clients` connections for `seconds`. */
double throughput(int port, int clients, double seconds);

typedef struct {
    samples_t error_us; /* |interval - period| over all clients */
    long lines;
    long missed;
    int clients_ok;
} autosend_result_t;
/* `clients` connections subscribe AUTOSEND("POS",10) for `seconds`. */
void autosend_run(int port, int clients, double seconds, autosend_result_t *r);

/* vtime.c: HOME/MOVE/GRIP/RELEASE cycles in stepped virtual time. */
typedef struct {
    int cycles_done;
    int cycles_failed;
    double virtual_s;
    double wall_s;
    long steps;
} vtime_result_t;
void vtime_run(int cycles, vtime_result_t *r);
/* The same cycles through a paused wsgsim and STEP(step_ms) on its control
 * channel (docs/simctl.md); step_ms 0: one RUN_UNTIL_DONE per command. */
void vtime_ctl_run(const server_t *srv, int cycles, int step_ms, vtime_result_t *r);
/* The same in parts: a session's cycles run in blocks, each adding to r. */
typedef struct {
    conn_t gcl;
    conn_t ctl;
    double sim_now_ms; /* where the server's clock stands (RUN_UNTIL_DONE only) */
} vtime_session_t;
void vtime_session_open(vtime_session_t *s, const server_t *srv);
void vtime_session_run(vtime_session_t *s, int cycles, int step_ms, vtime_result_t *r);
void vtime_session_close(vtime_session_t *s);
/* A paused server's device as its users see it: the fingers up (a
 * simulated second), homed, and the --part held (GRIP(20)). */
void vtime_hold_part(const server_t *srv);

/* scale.c: simulated ms per wall ms at each SCALE, over `seconds` each, on
 * a server with a control channel. */
#define SCALE_STEPS 3
typedef struct {
    double scale[SCALE_STEPS]; /* set by the caller */
    double rate[SCALE_STEPS];  /* measured; 0: not run */
} scale_result_t;
void scale_run(const server_t *srv, double seconds, scale_result_t *r);

/* instr.c: instructions the server executes per POS? (callgrind);
 * index 0: wsgsim (clock paused), 1: echo baseline; 0: not measured.
 * sequential_running: wsgsim with its clock running, less the timer work
 * of the run's wall time (running_idle_per_s instructions per second). */
typedef struct {
    double sequential[2];
    double pipelined[2];
    double sequential_running;
    double running_idle_per_s;
} instr_result_t;
void instr_run(const char *wsgsim, const char *self_exe, const char *out_dir, int seq_n, int pipe_n,
               instr_result_t *r);
/* The "summary:" (or "totals:") line of a callgrind output file: Ir. */
double callgrind_total(const char *path);

/* fleet.c: a base port with `count` free TCP and UDP loopback ports above it. */
int free_port_range(int count);

/* web.c: instructions per GET /api/devices/0/state and per event-stream
 * event (callgrind, the same difference method as instr.c); 0: not run. */
typedef struct {
    double per_state;
    double per_event;
} web_result_t;
void web_run(const char *wsgsim, const char *out_dir, int state_n, int event_n, web_result_t *r);

/* streams.c: 200 event streams (10 from each of 20 addresses) on a
 * free-running wsgsim, their events counted over a window while GCL POS?
 * round trips are timed against wsgsim and the echo baseline. */
#define WEB_EVENTS_PERIOD_MS_BENCH 40.0 /* host/web/web_events.h: 25 Hz */
typedef struct {
    int streams;            /* 0: not run */
    double expected_events; /* in the window, at the stream's rate */
    long min_events;        /* the stream that got the fewest */
    long median_events;
    double rtt_p99_us[2]; /* GCL POS? meanwhile: wsgsim, echo */
} streams_result_t;
void streams_run(const char *wsgsim, const char *out_dir, double seconds, int rtt_n,
                 const char *pin, streams_result_t *r);

/* subscribers.c: `clients` AUTOSEND("POS",10) subscriptions made while the
 * clock is paused (so they share one phase), then the clock resumed. */
typedef struct {
    int clients;
    int clients_ok;       /* subscriptions that delivered values */
    long lines;           /* values received in the window */
    long server_missed;   /* "missed" of every subscription (STATE?) */
    long client_gaps;     /* periods missing between arrivals */
    double wakeups_per_s; /* server context switches */
    double seconds;
} subscribers_result_t;
void subscribers_run(const char *wsgsim, const char *log_path, int clients, double seconds,
                     subscribers_result_t *r);

/* fleet.c: `--devices N` when wsgsim has it. */
typedef struct {
    bool available; /* false: wsgsim has no --devices option */
    int devices;
    double start_s; /* until the ready line */
    double idle_wakeups_per_s;
    double kib_per_device; /* RSS growth per device over a single device */
    double rtt_p50_us;     /* the slowest sampled device */
    double single_rtt_p50_us;
} fleet_result_t;
void fleet_run(const char *wsgsim, const char *out_dir, int devices, double idle_s, const char *pin,
               fleet_result_t *r);
/* `--devices N --address-per-device` (a cell of N addresses):
 * start until the ready line, peak RSS, idle wakeups, and whether the last
 * device's address answers SN? with its serial. */
typedef struct {
    int devices; /* 0: not run */
    double start_s;
    long peak_rss_kib; /* VmHWM */
    double idle_wakeups_per_s;
    bool last_answers;
} fleet_cell_result_t;
void fleet_cell_run(const char *wsgsim, const char *out_dir, int devices, double idle_s,
                    fleet_cell_result_t *r);

/* scripts.c: device 0 beside busy scripts on the fleet's other devices,
 * and FASTSTOP() while its own script runs work that cannot pause. */
typedef struct {
    int busy;                  /* 0: not run */
    double sn_p50_us[2];       /* SN? beside 1 and beside `busy` busy scripts */
    double faststop_p50_us[2]; /* FASTSTOP() the same */
    double freeze_faststop_ms; /* the slowest FASTSTOP() answer during a freeze */
} scripts_result_t;
void scripts_run(const char *wsgsim, const char *out_dir, int busy, scripts_result_t *r);

/* pace.c: a 100 mm MOVE at 100 mm/s (1.1 s simulated) in wall time, on a
 * quiet device and while another client sends POS? back to back. */
typedef struct {
    double quiet_s; /* 0: not run */
    double flooded_s;
    long polls; /* POS? answered during the flooded MOVE */
} pace_result_t;
void pace_run(const server_t *srv, pace_result_t *r);

/* timing.c: 1,000 POS? on the paused clock under --timing wsg50 and ideal. */
typedef struct {
    int requests; /* 0: not run */
    double wsg50_wall_s, ideal_wall_s;
    double wsg50_cpu_us, ideal_cpu_us; /* wsgsim's CPU time per request */
} timing_result_t;
void timing_run(const char *wsgsim, const char *out, timing_result_t *r);
/* proxy.c: POS? round trips directly and through the recording proxy, and
 * pipelined polling through it. */
typedef struct {
    samples_t direct, proxied; /* µs; proxied.n 0: not run */
    long pipelined, answered;  /* POS? written back to back, and answered */
    long expected_in_record;   /* every POS? that went through the proxy */
    long recorded_sent, recorded_answered;
} proxy_result_t;
void proxy_run(const char *wsgsim, const char *wsgproxy, const char *out_dir, int rtt_n,
               const char *pin, proxy_result_t *r);

/* physics.c: the default physics scene (--physics mujoco): a paused-clock
 * grip cycle (home, grip, hold 1 s, release) in wall time, and the running
 * clock's rate and wsgsim's share of one core during grip cycles. */
#define PHYSICS_PAUSED_CYCLES 5
typedef struct {
    bool measured;
    double paused_cycle_s;
    double running_rate;
    double running_cpu_pct;
} physics_result_t;
void physics_run(const char *wsgsim, const char *out_dir, physics_result_t *r);

#endif
