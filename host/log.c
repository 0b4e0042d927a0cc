#include "log.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "hal_clock.h"

#define LOG_LINE_MAX 1024
#define LOG_PEER_BURST 100 /* lines */
#define LOG_PEER_RATE 20.0 /* lines per second, once the burst is spent */

/* How a line reaches stderr without blocking. */
typedef enum {
    SINK_FILE,   /* a regular file or /dev/null: writes do not block */
    SINK_OWN_FD, /* a pipe or terminal reopened with O_NONBLOCK (own file description) */
    SINK_POLLED, /* could not reopen: write only when poll() says there is room */
    SINK_SOCKET, /* send(MSG_DONTWAIT) */
} sink_kind_t;

static struct {
    sink_kind_t kind;
    int fd;
    unsigned long dropped;  /* lines stderr could not take */
    unsigned long reported; /* of those, already reported */
} sink = {SINK_FILE, STDERR_FILENO, 0, 0};

static struct {
    double tokens;
    double refilled_s;
    unsigned long suppressed;
} peer_limit = {LOG_PEER_BURST, -1.0, 0};

static int log_verbose;

void host_log_set_verbose(int verbose)
{
    log_verbose = verbose;
}

/* The pipe or terminal gets a file description of its own, so O_NONBLOCK
 * does not leak to the shell or the parent that share stderr. */
void host_log_init(void)
{
    struct stat st;
    sink.kind = SINK_FILE;
    sink.fd = STDERR_FILENO;
    if (fstat(STDERR_FILENO, &st) != 0 || S_ISREG(st.st_mode)) {
        return;
    }
    if (S_ISSOCK(st.st_mode)) {
        sink.kind = SINK_SOCKET;
        return;
    }
    int fd = open("/proc/self/fd/2", O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_APPEND);
    if (fd >= 0) {
        sink.kind = SINK_OWN_FD;
        sink.fd = fd;
        return;
    }
    sink.kind = SINK_POLLED;
}

static bool room_to_write(void)
{
    struct pollfd p = {.fd = sink.fd, .events = POLLOUT, .revents = 0};
    return poll(&p, 1, 0) == 1 && (p.revents & POLLOUT) != 0;
}

/* One write of a whole line; false when it did not go out (now). */
static bool write_now(const char *text, size_t len)
{
    ssize_t n;
    if (sink.kind == SINK_SOCKET) {
        n = send(sink.fd, text, len, MSG_DONTWAIT | MSG_NOSIGNAL);
    } else if (sink.kind == SINK_POLLED && !room_to_write()) {
        n = -1;
    } else {
        n = write(sink.fd, text, len);
    }
    return n > 0; /* a terminal may take part of a line: the rest is lost, not waited for */
}

static size_t stamp(char *out, size_t cap, const char *what)
{
    uint64_t now = hal_clock_now_us();
    int n = snprintf(out, cap, "wsgsim [%llu.%06llu] %s: ", (unsigned long long)(now / 1000000u),
                     (unsigned long long)(now % 1000000u), what);
    return n < 0 ? 0 : ((size_t)n < cap ? (size_t)n : cap - 1);
}

/* Reports lines lost earlier before the next one goes out. */
static bool report_drops(void)
{
    if (sink.dropped == sink.reported) {
        return true;
    }
    char line[160];
    size_t len = stamp(line, sizeof(line), "warning");
    int n = snprintf(line + len, sizeof(line) - len,
                     "%lu log lines dropped (stderr was not being read)\n",
                     sink.dropped - sink.reported);
    if (n < 0 || !write_now(line, len + (size_t)n)) {
        return false;
    }
    sink.reported = sink.dropped;
    return true;
}

/* line holds len characters and has room for the '\n' added here. */
static void emit(char *line, size_t len)
{
    line[len] = '\n';
    if (!report_drops() || !write_now(line, len + 1)) {
        sink.dropped++;
    }
}

static const char *level_name(hal_log_level_t level)
{
    switch (level) {
    case HAL_LOG_DEBUG:
        return "debug";
    case HAL_LOG_INFO:
        return "info";
    case HAL_LOG_WARN:
        return "warning";
    case HAL_LOG_ERROR:
    default:
        return "error";
    }
}

static void vlog(hal_log_level_t level, const char *fmt, va_list args)
{
    char line[LOG_LINE_MAX];
    size_t len = stamp(line, sizeof(line), level_name(level));
    int n = vsnprintf(line + len, sizeof(line) - len - 1, fmt, args);
    len += n < 0 ? 0 : (size_t)n;
    emit(line, len < sizeof(line) - 2 ? len : sizeof(line) - 2);
}

void hal_log(hal_log_level_t level, const char *message)
{
    host_logf(level, "%s", message);
}

void host_logf(hal_log_level_t level, const char *fmt, ...)
{
    if (level == HAL_LOG_DEBUG && !log_verbose) {
        return;
    }
    va_list args;
    va_start(args, fmt);
    vlog(level, fmt, args);
    va_end(args);
}

static double monotonic_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

/* A token bucket on the wall clock: log volume is a real-world resource. */
static bool peer_line_allowed(void)
{
    double now = monotonic_s();
    if (peer_limit.refilled_s >= 0.0) {
        peer_limit.tokens += (now - peer_limit.refilled_s) * LOG_PEER_RATE;
    }
    if (peer_limit.tokens > LOG_PEER_BURST) {
        peer_limit.tokens = LOG_PEER_BURST;
    }
    peer_limit.refilled_s = now;
    if (peer_limit.tokens < 1.0) {
        peer_limit.suppressed++;
        return false;
    }
    peer_limit.tokens -= 1.0;
    return true;
}

void host_log_peer(hal_log_level_t level, const char *fmt, ...)
{
    if ((level == HAL_LOG_DEBUG && !log_verbose) || !peer_line_allowed()) {
        return;
    }
    if (peer_limit.suppressed > 0) {
        host_logf(HAL_LOG_WARN, "%lu messages about peers suppressed (rate limit)",
                  peer_limit.suppressed);
        peer_limit.suppressed = 0;
    }
    va_list args;
    va_start(args, fmt);
    vlog(level, fmt, args);
    va_end(args);
}

void host_log_line(const char *fmt, ...)
{
    char line[LOG_LINE_MAX];
    va_list args;
    va_start(args, fmt);
    int n = vsnprintf(line, sizeof(line) - 1, fmt, args);
    va_end(args);
    size_t len = n < 0 ? 0 : (size_t)n;
    emit(line, len < sizeof(line) - 2 ? len : sizeof(line) - 2);
}

unsigned long host_log_dropped(void)
{
    return sink.dropped;
}
