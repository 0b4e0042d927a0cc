/* SPDX-License-Identifier: BSD-3-Clause */
/* The candump -L writer (can_log.h). */
#include "can_log.h"

#include <errno.h>
#include <string.h>

#define CAN_LOG_LINE_MAX 64

/* Formats one frame as a candump -L line, without the newline; returns the
 * length (out_line holds at least CAN_LOG_LINE_MAX bytes). */
static int can_log_format(const hal_can_frame_t *frame, uint64_t time_us, char *out_line)
{
    bool ext = (frame->flags & HAL_CAN_FLAG_EXT) != 0u;
    unsigned dlc = frame->dlc <= HAL_CAN_MAX_DLC ? frame->dlc : HAL_CAN_MAX_DLC;
    int n =
        snprintf(out_line, CAN_LOG_LINE_MAX,
                 ext ? "(%010llu.%06llu) %s %08lX#" : "(%010llu.%06llu) %s %03lX#",
                 (unsigned long long)(time_us / 1000000u), (unsigned long long)(time_us % 1000000u),
                 CAN_LOG_IFACE,
                 (unsigned long)(frame->id & (ext ? HAL_CAN_EXT_ID_MASK : HAL_CAN_STD_ID_MASK)));
    if ((frame->flags & HAL_CAN_FLAG_RTR) != 0u) {
        n += dlc > 0u ? snprintf(out_line + n, CAN_LOG_LINE_MAX - (size_t)n, "R%u", dlc)
                      : snprintf(out_line + n, CAN_LOG_LINE_MAX - (size_t)n, "R");
        return n;
    }
    for (unsigned i = 0; i < dlc; i++) {
        n += snprintf(out_line + n, CAN_LOG_LINE_MAX - (size_t)n, "%02X", frame->data[i]);
    }
    return n;
}

void can_log_frame(can_log_t *log, const hal_can_frame_t *frame, uint64_t time_us)
{
    if (log->out == NULL) {
        return;
    }
    char line[CAN_LOG_LINE_MAX];
    int n = can_log_format(frame, time_us, line);
    fprintf(log->out, "%.*s\n", n, line);
}

bool can_log_open(can_log_t *log, const char *path)
{
    log->out = fopen(path, "w");
    if (log->out == NULL) {
        fprintf(stderr, "wsgsim: cannot write --can-log file %s: %s\n", path, strerror(errno));
        return false;
    }
    log->path = path;
    return true;
}

bool can_log_reopen(can_log_t *log)
{
    if (log->out == NULL) {
        return true;
    }
    FILE *f = fopen(log->path, "a");
    if (f == NULL) {
        return false;
    }
    fclose(log->out);
    log->out = f;
    return true;
}

void can_log_close(can_log_t *log)
{
    if (log->out != NULL) {
        fclose(log->out);
        log->out = NULL;
    }
}
