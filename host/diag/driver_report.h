/* SPDX-License-Identifier: BSD-3-Clause */
/* The report on the driver under test: what each session (a TCP
 * connection, a UDP peer of a protocol) did that a real gripper would
 * answer differently from wsgsim's instant, lossless service: its request
 * rate and peak, requests pipelined behind an unanswered one, queries
 * polled during a motion, refusals by reason, streams it subscribed and
 * did not read, closes without goodbye, unfinished messages at close,
 * reconnects and the FAST STOPs it caused (docs/testing-your-driver.md).
 *
 * Counted server-side from the coverage's observers (coverage.c forwards
 * them: no observer of its own, so the request path pays no second list
 * walk); live sessions are kept by id, ended ones as totals plus the last
 * DRIVER_ENDED_KEPT of them, so the report covers the whole run in bounded
 * memory. */
#ifndef HOST_DRIVER_REPORT_H
#define HOST_DRIVER_REPORT_H

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stddef.h>

#include "wsg/wsg_conn.h"

#define DRIVER_ENDED_KEPT 32u

typedef struct driver_report driver_report_t;

/* What a device's GCL command observer looks at before it calls in: only
 * a query during a motion, FASTSTOP and AUTOSEND are counted per command,
 * so the common request pays a few compares (driver_report_watch()). */
typedef struct {
    bool moving;          /* SF_MOVING, as the last sampled flags show it */
    int faststop_command; /* GCL command table indices */
    int autosend_command;
} driver_watch_t;

/* What only the port knows of a session: its peer ("ADDR:PORT") and the
 * updates it dropped because the client did not read them. */
typedef struct {
    const char *(*peer_name)(void *ctx, const wsg_conn_t *c);
    unsigned long (*updates_dropped)(void *ctx, const wsg_conn_t *c);
    void *ctx;
} driver_port_t;

/* NULL when out of memory. */
driver_report_t *driver_report_create(unsigned devices);
void driver_report_destroy(driver_report_t *r);
/* port may be NULL (no peers, no drops known); the caller keeps it. r may
 * be NULL (the report is not counted): nothing. */
void driver_report_set_port(driver_report_t *r, const driver_port_t *port);
void driver_report_attach(driver_report_t *r, wsg_device_t *dev, unsigned index);
/* Forgets every ended session and zeroes the live ones' counts. */
void driver_report_reset(driver_report_t *r);
/* The process stops: sessions closed from now on were still open at exit,
 * not dropped by their client. */
void driver_report_stopping(driver_report_t *r);
/* Device index is power-cycled (the control channel's RESET): its sessions
 * end as "reset", before their connections drop unobserved. NULL: nothing. */
void driver_report_power_cycle(driver_report_t *r, unsigned index);

/* The events, from coverage.c's observers of device `index`: a read
 * (requests are counted per read, from the connection's own count); the
 * sampled flags (SF_MOVING: a query now polls during a motion). */
void driver_report_read(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                        const uint8_t *bytes, size_t len);
void driver_report_flags(driver_report_t *r, unsigned index, uint32_t flags);
/* A binary frame in or out (driver_report_message_in/_out tell them from
 * GCL lines inline: a GCL request pays two compares). */
void driver_report_bin_request(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                               const unsigned char *frame, size_t len);
void driver_report_bin_reply(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                             const unsigned char *frame, size_t len);

#define DRIVER_BIN_PREAMBLE 0xAAu
#define DRIVER_BIN_REQUEST_MIN 8u /* preamble, ID, length, CRC */
#define DRIVER_BIN_REPLY_MIN 10u  /* and the status */

static inline void driver_report_message_in(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                                            const char *bytes, size_t len)
{
    const unsigned char *frame = (const unsigned char *)bytes;
    if (len >= DRIVER_BIN_REQUEST_MIN && frame[0] == DRIVER_BIN_PREAMBLE) {
        driver_report_bin_request(r, index, c, frame, len);
    }
}

static inline void driver_report_message_out(driver_report_t *r, unsigned index,
                                             const wsg_conn_t *c, const char *bytes, size_t len)
{
    const unsigned char *frame = (const unsigned char *)bytes;
    if (len >= DRIVER_BIN_REPLY_MIN && frame[0] == DRIVER_BIN_PREAMBLE) {
        driver_report_bin_reply(r, index, c, frame, len);
    }
}
/* The device's watch (NULL before attach); it stays where it is. */
const driver_watch_t *driver_report_watch(const driver_report_t *r, unsigned index);
/* Only for a command driver_report_watches(). */
void driver_report_gcl_command(driver_report_t *r, unsigned index, const wsg_conn_t *c, int command,
                               unsigned form, wsg_status_t status);

static inline bool driver_report_watches(const driver_watch_t *w, int command)
{
    return w->moving || command == w->faststop_command || command == w->autosend_command;
}
void driver_report_gcl_error(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                             wsg_status_t status);
void driver_report_closed(driver_report_t *r, unsigned index, const wsg_conn_t *c,
                          wsg_close_reason_t why, bool fast_stop);

/* The "driver" section of the coverage report (and DRIVER?). */
cJSON *driver_report_json(const driver_report_t *r);
/* The short human summary, one behaviour per line (malloc'd; free() it). */
char *driver_report_text(const driver_report_t *r);

#endif
