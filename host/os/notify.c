/* SPDX-License-Identifier: BSD-3-Clause */
/* Readiness reports (notify.h). */
#include "notify.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <systemd/sd-daemon.h>
#include <unistd.h>

#include "log.h"

static void put_port(FILE *f, const char *name, int port)
{
    if (port >= 0) {
        fprintf(f, "%s=%d\n", name, port);
    }
}

static bool temp_path(const char *path, char *out, size_t cap)
{
    if (snprintf(out, cap, "%s.tmp", path) >= (int)cap) {
        errno = ENAMETOOLONG;
        return false;
    }
    return true;
}

/* Written beside the target, renamed over it by notify_ready(): a reader
 * never sees half a file. */
bool notify_prepare(const char *ready_file, const notify_ports_t *ports)
{
    char tmp[PATH_MAX];
    FILE *f = NULL;
    if (ready_file == NULL) {
        return true;
    }
    if (temp_path(ready_file, tmp, sizeof(tmp)) && (f = fopen(tmp, "w")) != NULL) {
        fprintf(f, "pid=%ld\n", (long)getpid());
        put_port(f, "tcp_port", ports->tcp_port);
        put_port(f, "udp_port", ports->udp_port);
        put_port(f, "sim_port", ports->sim_port);
        put_port(f, "bin_tcp_port", ports->bin_tcp_port);
        put_port(f, "bin_udp_port", ports->bin_udp_port);
        put_port(f, "http_port", ports->http_port);
        bool written = ferror(f) == 0;
        if (fclose(f) == 0 && written) {
            return true;
        }
        unlink(tmp);
    }
    fprintf(stderr, "wsgsim: cannot write --ready-file %s: %s\n", ready_file, strerror(errno));
    return false;
}

bool notify_ready(const char *ready_file, const char *status)
{
    char tmp[PATH_MAX];
    if (ready_file != NULL) {
        if (!temp_path(ready_file, tmp, sizeof(tmp)) || rename(tmp, ready_file) != 0) {
            host_logf(HAL_LOG_ERROR, "cannot write --ready-file %s: %s", ready_file,
                      strerror(errno));
            return false;
        }
        host_logf(HAL_LOG_DEBUG, "ready file %s written", ready_file);
    }
    int sent = sd_notifyf(0, "READY=1\nSTATUS=%s\nMAINPID=%ld", status, (long)getpid());
    if (sent > 0) {
        host_logf(HAL_LOG_DEBUG, "READY=1 sent to systemd");
    } else if (sent < 0) {
        host_logf(HAL_LOG_WARN, "cannot notify systemd ($NOTIFY_SOCKET): %s", strerror(-sent));
    }
    return true;
}

void notify_stopping(const char *ready_file)
{
    sd_notify(0, "STOPPING=1");
    if (ready_file != NULL) {
        unlink(ready_file);
    }
}
