/* SPDX-License-Identifier: BSD-3-Clause */
/* Child processes under test and what /proc tells about them. */
#include <arpa/inet.h>
#include <fcntl.h>
#include <sched.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench.h"

#define START_TIMEOUT_US 10e6
#define CHILDREN_MAX 4

static pid_t children[CHILDREN_MAX];

static void remember(pid_t pid)
{
    for (int i = 0; i < CHILDREN_MAX; i++) {
        if (children[i] == 0) {
            children[i] = pid;
            return;
        }
    }
}

static void forget(pid_t pid)
{
    for (int i = 0; i < CHILDREN_MAX; i++) {
        if (children[i] == pid) {
            children[i] = 0;
        }
    }
}

void server_kill_all(void)
{
    for (int i = 0; i < CHILDREN_MAX; i++) {
        if (children[i] > 0) {
            kill(children[i], SIGKILL);
            waitpid(children[i], NULL, 0);
            children[i] = 0;
        }
    }
}

/* In the child: die with the benchmark, however it ends. */
static void follow_parent(void)
{
    prctl(PR_SET_PDEATHSIG, SIGKILL);
}

static const char *extra_args[WSGSIM_EXTRA_ARGS_MAX];
static int extra_count;

void server_add_wsgsim_arg(const char *arg)
{
    if (extra_count == WSGSIM_EXTRA_ARGS_MAX) {
        die("too many --wsgsim-arg options");
    }
    extra_args[extra_count++] = arg;
}

int wsgsim_argv(const char **argv, int cap, const char *binary, bool paused)
{
    static const char *const common[] = {"--bind",
                                         "127.0.0.1",
                                         "--tcp-port",
                                         "0",
                                         "--udp-port",
                                         "0",
                                         "--max-clients",
                                         "128",
                                         "--no-disconnect-faststop"};
    static const char *const paused_args[] = {"--part", "30", "--sim-port", "0", "--start-paused"};
    int n = 0;
    argv[n++] = binary;
    for (size_t i = 0; i < sizeof(common) / sizeof(common[0]); i++) {
        argv[n++] = common[i];
    }
    for (size_t i = 0; paused && i < sizeof(paused_args) / sizeof(paused_args[0]); i++) {
        argv[n++] = paused_args[i];
    }
    for (int i = 0; i < extra_count; i++) {
        argv[n++] = extra_args[i];
    }
    if (n >= cap) {
        die("too many wsgsim arguments");
    }
    argv[n] = NULL;
    return n;
}

/* In the child: stderr to the log, then the command. */
static void exec_logged(const char *const *argv, const char *log_path)
{
    follow_parent();
    int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
        _exit(126);
    }
    dup2(fd, STDERR_FILENO);
    close(fd);
    execvp(argv[0], (char *const *)argv);
    _exit(127);
}

static bool read_ready(const char *log_path, server_t *srv)
{
    FILE *f = fopen(log_path, "r");
    if (f == NULL) {
        return false;
    }
    char line[512];
    bool found = false;
    while (!found && fgets(line, sizeof(line), f) != NULL) {
        const char *at = strstr(line, "ready: tcp ");
        srv->ctl_port = 0;
        found = at != NULL && sscanf(at, "ready: tcp %*[^:]:%d, udp %*[^:]:%d", &srv->tcp_port,
                                     &srv->udp_port) == 2;
        /* other listeners (binary UDP) may come between udp and control */
        const char *control = found ? strstr(at, ", control ") : NULL;
        if (control != NULL && sscanf(control, ", control %*[^:]:%d", &srv->ctl_port) != 1) {
            srv->ctl_port = 0;
        }
    }
    fclose(f);
    return found;
}

bool server_start_cmd(server_t *srv, const char *name, const char *const *argv,
                      const char *log_path, double timeout_s)
{
    memset(srv, 0, sizeof(*srv));
    srv->name = name;
    unlink(log_path); /* never read the ready line of an earlier run */
    srv->pid = fork();
    if (srv->pid == 0) {
        exec_logged(argv, log_path);
    }
    remember(srv->pid);
    double deadline = now_us() + timeout_s * 1e6;
    while (now_us() < deadline) {
        if (read_ready(log_path, srv)) {
            return true;
        }
        if (waitpid(srv->pid, NULL, WNOHANG) == srv->pid) {
            forget(srv->pid);
            srv->pid = 0;
            return false;
        }
        usleep(10000);
    }
    server_stop(srv);
    return false;
}

bool server_start_wsgsim(server_t *srv, const char *binary, const char *log_path, bool paused)
{
    const char *argv[48];
    wsgsim_argv(argv, 48, binary, paused);
    return server_start_cmd(srv, "wsgsim", argv, log_path, START_TIMEOUT_US / 1e6);
}

static int bound_socket(int type, int *port)
{
    int fd = socket(AF_INET, type | SOCK_CLOEXEC, 0);
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = 0};
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof(sa);
    if (fd < 0 || bind(fd, (struct sockaddr *)&sa, sizeof(sa)) != 0 ||
        (type == SOCK_STREAM && listen(fd, 256) != 0) ||
        getsockname(fd, (struct sockaddr *)&sa, &len) != 0) {
        die("echo server: cannot bind a loopback socket");
    }
    *port = ntohs(sa.sin_port);
    return fd;
}

void echo_server_main(void)
{
    int tcp_port;
    int udp_port;
    int tcp_fd = bound_socket(SOCK_STREAM, &tcp_port);
    int udp_fd = bound_socket(SOCK_DGRAM, &udp_port);
    fprintf(stderr, "echo ready: tcp 127.0.0.1:%d, udp 127.0.0.1:%d\n", tcp_port, udp_port);
    echo_server_run(tcp_fd, udp_fd);
}

/* Forks a baseline server on two sockets bound already: returns 0 in the
 * child, which serves on them; the parent keeps neither. */
static pid_t fork_baseline(server_t *srv, const char *name, int fd_a, int fd_b)
{
    srv->name = name;
    srv->pid = fork();
    if (srv->pid == 0) {
        follow_parent();
        return 0;
    }
    remember(srv->pid);
    close(fd_a);
    close(fd_b);
    return srv->pid;
}

bool server_start_echo(server_t *srv)
{
    memset(srv, 0, sizeof(*srv));
    int tcp_fd = bound_socket(SOCK_STREAM, &srv->tcp_port);
    int udp_fd = bound_socket(SOCK_DGRAM, &srv->udp_port);
    if (fork_baseline(srv, "echo", tcp_fd, udp_fd) == 0) {
        echo_server_run(tcp_fd, udp_fd);
    }
    return srv->pid > 0;
}

bool server_start_responder(server_t *srv, double ms_per_command)
{
    memset(srv, 0, sizeof(*srv));
    int gcl_fd = bound_socket(SOCK_STREAM, &srv->tcp_port);
    int ctl_fd = bound_socket(SOCK_STREAM, &srv->ctl_port);
    if (fork_baseline(srv, "responder", gcl_fd, ctl_fd) == 0) {
        responder_server_run(gcl_fd, ctl_fd, ms_per_command);
    }
    return srv->pid > 0;
}

bool server_stop_within(server_t *srv, double seconds)
{
    if (srv->pid <= 0) {
        return true;
    }
    forget(srv->pid);
    kill(srv->pid, SIGTERM);
    int status = 0;
    for (double waited = 0; waited < seconds; waited += 0.01) {
        if (waitpid(srv->pid, &status, WNOHANG) == srv->pid) {
            srv->pid = 0;
            return WIFEXITED(status) || (WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
        }
        usleep(10000);
    }
    kill(srv->pid, SIGKILL);
    waitpid(srv->pid, NULL, 0);
    srv->pid = 0;
    return false;
}

void server_stop(server_t *srv)
{
    server_stop_within(srv, 5.0);
}

/* /proc/PID/schedstat: nanoseconds on the CPU (finer than the 10 ms ticks
 * of /proc/PID/stat). */
double proc_cpu_us(pid_t pid)
{
    char path[64];
    snprintf(path, sizeof(path), "/proc/%d/schedstat", (int)pid);
    FILE *f = fopen(path, "r");
    unsigned long long ns = 0;
    if (f != NULL) {
        int got = fscanf(f, "%llu", &ns);
        fclose(f);
        if (got == 1) {
            return (double)ns / 1e3;
        }
    }
    snprintf(path, sizeof(path), "/proc/%d/stat", (int)pid);
    f = fopen(path, "r");
    unsigned long ut = 0, st = 0;
    if (f == NULL) {
        return -1.0;
    }
    int got = fscanf(f, "%*d %*s %*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu", &ut, &st);
    fclose(f);
    return got == 2 ? (double)(ut + st) * 1e6 / (double)sysconf(_SC_CLK_TCK) : -1.0;
}

static long status_field(pid_t pid, const char *key)
{
    char path[64];
    char line[256];
    long value = -1;
    size_t klen = strlen(key);
    snprintf(path, sizeof(path), "/proc/%d/status", (int)pid);
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        return -1;
    }
    while (fgets(line, sizeof(line), f) != NULL) {
        if (strncmp(line, key, klen) == 0 && line[klen] == ':') {
            value = strtol(line + klen + 1, NULL, 10);
        }
    }
    fclose(f);
    return value;
}

long proc_rss_kib(pid_t pid)
{
    return status_field(pid, "VmRSS");
}

long proc_hwm_kib(pid_t pid)
{
    return status_field(pid, "VmHWM");
}

long proc_ctx_switches(pid_t pid)
{
    long v = status_field(pid, "voluntary_ctxt_switches");
    long n = status_field(pid, "nonvoluntary_ctxt_switches");
    return v < 0 || n < 0 ? -1 : v + n;
}

long proc_wakeups(pid_t pid)
{
    return status_field(pid, "voluntary_ctxt_switches");
}

/* CPU placement for the round trips. Unpinned, a sequential round trip
 * costs one or two cross-CPU wakeups or none, depending on where the
 * scheduler happens to put each server (on a VM about 40 us each way), which
 * swamps the difference between the servers. "same": the client and the
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

/* The servers' CPU for the round trips of `mode`: the client's with
 * "same", the next one with "cross". */
static int servers_cpu(const char *mode)
{
    return strcmp(mode, "cross") == 0 ? online_cpu(1) : online_cpu(0);
}

void place_round_trips(server_t *const *srv, int n, const char *mode, char *placement, size_t cap)
{
    int client = online_cpu(0);
    int server = servers_cpu(mode);
    if (strcmp(mode, "none") == 0 || client < 0 || server < 0) {
        snprintf(placement, cap, "unpinned");
        return;
    }
    set_cpu(0, client);
    for (int k = 0; k < n; k++) {
        set_cpu(srv[k]->pid, server);
    }
    snprintf(placement, cap, "client on CPU %d, servers on CPU %d", client, server);
}

void place_apart(pid_t pid, const char *mode)
{
    int other = servers_cpu(mode) == online_cpu(0) ? online_cpu(1) : online_cpu(0);
    if (strcmp(mode, "none") != 0 && other >= 0) {
        set_cpu(pid, other);
    }
}

void unplace_round_trips(server_t *const *srv, int n)
{
    set_cpu(0, -1);
    for (int k = 0; k < n; k++) {
        set_cpu(srv[k]->pid, -1);
    }
}
