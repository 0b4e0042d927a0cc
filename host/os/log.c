/* SPDX-License-Identifier: BSD-3-Clause */
#include "log.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "hal_clock.h"

#define LOG_LINE_MAX 1024
#define LOG_LIMIT_BURST 100 /* lines */
#define LOG_LIMIT_RATE 20.0 /* lines per second, once the burst is spent */
#define LOG_RECENT_LINES 100
#define LOG_RECENT_LINE_MAX 256 /* longer lines are kept cut */

/* Where stderr leads. */
typedef enum {
    SINK_FILE,   /* a regular file or /dev/null: writes do not block */
    SINK_OWN_FD, /* a pipe or terminal reopened with O_NONBLOCK (own file description) */
    SINK_POLLED, /* could not reopen: write only when poll() says there is room */
    SINK_SOCKET, /* send(MSG_DONTWAIT) */
} sink_kind_t;

/* How a line reaches stderr without blocking. */
typedef struct {
    sink_kind_t kind;
    int fd;
    unsigned long dropped;  /* lines stderr could not take */
    unsigned long reported; /* of those, already reported */
} sink_t;

/* A token bucket of rate-limited lines: host_log_peer()'s, host_log_script()'s. */
typedef struct {
    double tokens;
    double refilled_s;
    unsigned long suppressed;
    const char *what; /* in the summary: "N <what> suppressed" */
} log_limit_t;

/* The last lines logged, numbered from 0, for the web page's system view
 * (host_log_recent); kept whether or not stderr took them. */
typedef struct {
    char lines[LOG_RECENT_LINES][LOG_RECENT_LINE_MAX];
    uint64_t next; /* the number the next line gets */
} recent_t;

/* The process's one log, and the one piece of state it keeps: the device's
 * log is hal_log() (hal/hal_log.h), a link-time function without a context
 * pointer that the firmware calls from anywhere, and it writes to the
 * process's stderr (or --log-file), which every module shares. */
static struct {
    sink_t sink;
    log_limit_t peer_limit;
    log_limit_t script_limit;
    recent_t recent;
    hal_log_level_t min_level;
    bool wall_timestamps;
    const char *path; /* --log-file; NULL: stderr */
} the_log = {
    .sink = {SINK_FILE, STDERR_FILENO, 0, 0},
    .peer_limit = {LOG_LIMIT_BURST, -1.0, 0, "messages about peers"},
    .script_limit = {LOG_LIMIT_BURST, -1.0, 0, "lines from scripts"},
    .min_level = HAL_LOG_INFO,
};

void host_log_set_level(hal_log_level_t level)
{
    the_log.min_level = level;
}

bool host_log_parse_level(const char *name, hal_log_level_t *level)
{
    static const struct {
        const char *name;
        hal_log_level_t level;
    } names[] = {{"error", HAL_LOG_ERROR},
                 {"warn", HAL_LOG_WARN},
                 {"warning", HAL_LOG_WARN},
                 {"info", HAL_LOG_INFO},
                 {"debug", HAL_LOG_DEBUG}};
    for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++) {
        if (strcmp(name, names[i].name) == 0) {
            *level = names[i].level;
            return true;
        }
    }
    return false;
}

void host_log_set_timestamps(bool on)
{
    the_log.wall_timestamps = on;
}

static int open_log_file(const char *path)
{
    return open(path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
}

bool host_log_open_file(const char *path)
{
    int fd = open_log_file(path);
    if (fd < 0) {
        fprintf(stderr, "wsgsim: cannot write --log-file %s: %s\n", path, strerror(errno));
        return false;
    }
    the_log.path = path;
    the_log.sink.kind = SINK_FILE;
    the_log.sink.fd = fd;
    return true;
}

void host_log_reopen(void)
{
    if (the_log.path == NULL) {
        return;
    }
    int fd = open_log_file(the_log.path);
    if (fd < 0) {
        host_logf(HAL_LOG_ERROR, "cannot reopen --log-file %s: %s (still writing the old file)",
                  the_log.path, strerror(errno));
        return;
    }
    close(the_log.sink.fd);
    the_log.sink.fd = fd;
    host_logf(HAL_LOG_INFO, "log file reopened");
}

/* The pipe or terminal gets a file description of its own, so O_NONBLOCK
 * does not leak to the shell or the parent that share stderr. */
void host_log_init(void)
{
    struct stat st;
    the_log.sink.kind = SINK_FILE;
    the_log.sink.fd = STDERR_FILENO;
    if (fstat(STDERR_FILENO, &st) != 0 || S_ISREG(st.st_mode)) {
        return;
    }
    if (S_ISSOCK(st.st_mode)) {
        the_log.sink.kind = SINK_SOCKET;
        return;
    }
    int fd = open("/proc/self/fd/2", O_WRONLY | O_NONBLOCK | O_CLOEXEC | O_APPEND);
    if (fd >= 0) {
        the_log.sink.kind = SINK_OWN_FD;
        the_log.sink.fd = fd;
        return;
    }
    the_log.sink.kind = SINK_POLLED;
}

static bool room_to_write(void)
{
    struct pollfd p = {.fd = the_log.sink.fd, .events = POLLOUT, .revents = 0};
    return poll(&p, 1, 0) == 1 && (p.revents & POLLOUT) != 0;
}

/* One write of a whole line; false when it did not go out (now). */
static bool write_now(const char *text, size_t len)
{
    ssize_t n;
    if (the_log.sink.kind == SINK_SOCKET) {
        n = send(the_log.sink.fd, text, len, MSG_DONTWAIT | MSG_NOSIGNAL);
    } else if (the_log.sink.kind == SINK_POLLED && !room_to_write()) {
        n = -1;
    } else {
        n = write(the_log.sink.fd, text, len);
    }
    return n > 0; /* a terminal may take part of a line: the rest is lost, not waited for */
}

/* "2024-05-01T12:00:00.123Z " when --log-timestamps is on, else nothing. */
static size_t wall_stamp(char *out, size_t cap)
{
    struct timespec now;
    struct tm utc;
    if (!the_log.wall_timestamps || clock_gettime(CLOCK_REALTIME, &now) != 0 ||
        gmtime_r(&now.tv_sec, &utc) == NULL) {
        return 0;
    }
    size_t len = strftime(out, cap, "%Y-%m-%dT%H:%M:%S", &utc);
    int n = snprintf(out + len, cap - len, ".%03ldZ ", now.tv_nsec / 1000000L);
    return n < 0 ? len : len + (size_t)n;
}

/* Simulated time in brackets: it orders the log with the --record file. */
static size_t stamp(char *out, size_t cap, const char *what)
{
    size_t len = wall_stamp(out, cap);
    uint64_t now = hal_clock_now_us();
    int n = snprintf(out + len, cap - len,
                     "wsgsim [%llu.%06llu] %s: ", (unsigned long long)(now / 1000000u),
                     (unsigned long long)(now % 1000000u), what);
    len += n < 0 ? 0 : (size_t)n;
    return len < cap ? len : cap - 1;
}

/* Reports lines lost earlier before the next one goes out. */
static bool report_drops(void)
{
    if (the_log.sink.dropped == the_log.sink.reported) {
        return true;
    }
    char line[160];
    size_t len = stamp(line, sizeof(line), "warning");
    int n = snprintf(line + len, sizeof(line) - len,
                     "%lu log lines dropped (stderr was not being read)\n",
                     the_log.sink.dropped - the_log.sink.reported);
    if (n < 0 || !write_now(line, len + (size_t)n)) {
        return false;
    }
    the_log.sink.reported = the_log.sink.dropped;
    return true;
}

static void keep_recent(const char *line, size_t len)
{
    char *slot = the_log.recent.lines[the_log.recent.next % LOG_RECENT_LINES];
    size_t kept = len < LOG_RECENT_LINE_MAX - 1 ? len : LOG_RECENT_LINE_MAX - 1;
    while (kept < len && kept > 0 && ((unsigned char)line[kept] & 0xC0u) == 0x80u) {
        kept--; /* cut before a UTF-8 sequence, not inside it: the page reads JSON */
    }
    memcpy(slot, line, kept);
    slot[kept] = '\0';
    the_log.recent.next++;
}

size_t host_log_recent(uint64_t since, const char **lines, size_t cap, uint64_t *next)
{
    uint64_t oldest =
        the_log.recent.next > LOG_RECENT_LINES ? the_log.recent.next - LOG_RECENT_LINES : 0;
    size_t n = 0;
    for (uint64_t i = since > oldest ? since : oldest; i < the_log.recent.next && n < cap; i++) {
        lines[n++] = the_log.recent.lines[i % LOG_RECENT_LINES];
    }
    *next = the_log.recent.next;
    return n;
}

/* line holds len characters and has room for the '\n' added here. */
static void emit(char *line, size_t len)
{
    keep_recent(line, len);
    line[len] = '\n';
    if (!report_drops() || !write_now(line, len + 1)) {
        the_log.sink.dropped++;
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

/* Control bytes in a message (a CR, an ESC that a terminal would obey)
 * become \xHH; the line is cut where it is full. */
static size_t escape_controls(char *text, size_t len, size_t cap)
{
    size_t first = 0;
    while (first < len && (unsigned char)text[first] >= 0x20u && text[first] != 0x7f) {
        first++;
    }
    if (first == len) {
        return len;
    }
    char rest[LOG_LINE_MAX];
    size_t rest_len = len - first;
    memcpy(rest, text + first, rest_len);
    size_t out = first;
    for (size_t i = 0; i < rest_len && out + 4 < cap; i++) {
        unsigned char c = (unsigned char)rest[i];
        if (c < 0x20u || c == 0x7fu) {
            out += (size_t)snprintf(text + out, cap - out, "\\x%02X", c);
        } else {
            text[out++] = (char)c;
        }
    }
    return out;
}

static void vlog(hal_log_level_t level, const char *fmt, va_list args)
{
    char line[LOG_LINE_MAX];
    size_t len = stamp(line, sizeof(line), level_name(level));
    int n = vsnprintf(line + len, sizeof(line) - len - 1, fmt, args);
    size_t message = n < 0 ? 0 : (size_t)n;
    if (message > sizeof(line) - len - 2) {
        message = sizeof(line) - len - 2;
    }
    len += escape_controls(line + len, message, sizeof(line) - len - 1);
    emit(line, len < sizeof(line) - 2 ? len : sizeof(line) - 2);
}

void hal_log(hal_log_level_t level, const char *message)
{
    host_logf(level, "%s", message);
}

void host_logf(hal_log_level_t level, const char *fmt, ...)
{
    if (level < the_log.min_level) {
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

/* A token bucket on the wall clock: log volume is a real-world resource.
 * The first line let through after some were suppressed is preceded by
 * their count. */
static bool line_allowed(log_limit_t *limit)
{
    double now = monotonic_s();
    if (limit->refilled_s >= 0.0) {
        limit->tokens += (now - limit->refilled_s) * LOG_LIMIT_RATE;
    }
    if (limit->tokens > LOG_LIMIT_BURST) {
        limit->tokens = LOG_LIMIT_BURST;
    }
    limit->refilled_s = now;
    if (limit->tokens < 1.0) {
        limit->suppressed++;
        return false;
    }
    limit->tokens -= 1.0;
    if (limit->suppressed > 0) {
        host_logf(HAL_LOG_WARN, "%lu %s suppressed (rate limit)", limit->suppressed, limit->what);
        limit->suppressed = 0;
    }
    return true;
}

void host_log_peer(hal_log_level_t level, const char *fmt, ...)
{
    if (level < the_log.min_level || !line_allowed(&the_log.peer_limit)) {
        return;
    }
    va_list args;
    va_start(args, fmt);
    vlog(level, fmt, args);
    va_end(args);
}

/* Printable ASCII stays, a backslash doubles, any other byte is \xHH:
 * the log and the terminal behind it get no control of their own. */
static size_t escape_printable(const char *text, size_t len, char *out, size_t cap)
{
    size_t n = 0;
    for (size_t i = 0; i < len && n + 5 <= cap; i++) {
        unsigned char c = (unsigned char)text[i];
        if (c == '\\') {
            out[n++] = '\\';
            out[n++] = '\\';
        } else if (c >= 0x20u && c < 0x7fu) {
            out[n++] = (char)c;
        } else {
            n += (size_t)snprintf(out + n, cap - n, "\\x%02X", c);
        }
    }
    out[n] = '\0';
    return n;
}

void host_log_script(hal_log_level_t level, const char *who, const char *text, size_t len)
{
    if (level < the_log.min_level || !line_allowed(&the_log.script_limit)) {
        return;
    }
    char escaped[LOG_LINE_MAX];
    escape_printable(text, len, escaped, sizeof(escaped));
    host_logf(level, "%s: %s", who, escaped);
}

void host_log_line(const char *fmt, ...)
{
    char line[LOG_LINE_MAX];
    size_t len = wall_stamp(line, sizeof(line));
    va_list args;
    va_start(args, fmt);
    int n = vsnprintf(line + len, sizeof(line) - len - 1, fmt, args);
    va_end(args);
    len += n < 0 ? 0 : (size_t)n;
    emit(line, len < sizeof(line) - 2 ? len : sizeof(line) - 2);
}
