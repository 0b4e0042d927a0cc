#include "log.h"

#include <stdarg.h>
#include <stdio.h>

#include "hal_clock.h"

static int log_verbose;

void host_log_set_verbose(int verbose)
{
    log_verbose = verbose;
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

void hal_log(hal_log_level_t level, const char *message)
{
    host_logf(level, "%s", message);
}

void host_logf(hal_log_level_t level, const char *fmt, ...)
{
    if (level == HAL_LOG_DEBUG && !log_verbose) {
        return;
    }
    uint64_t now = hal_clock_now_us();
    fprintf(stderr, "wsgsim [%llu.%06llu] %s: ", (unsigned long long)(now / 1000000u),
            (unsigned long long)(now % 1000000u), level_name(level));
    va_list args;
    va_start(args, fmt);
    vfprintf(stderr, fmt, args);
    va_end(args);
    fputc('\n', stderr);
}
