/* SPDX-License-Identifier: BSD-3-Clause */
/* What the driver report's two files share: one session's counts
 * (driver_report.c counts them, driver_report_out.c reports them). */
#ifndef HOST_DRIVER_REPORT_INTERNAL_H
#define HOST_DRIVER_REPORT_INTERNAL_H

#include <stdint.h>

#include "driver_report.h"
#include "list.h"
#include "wsg/wsg_status.h"

#define DRIVER_BUCKETS 256u
#define DRIVER_PEER_MAX 64

/* The behaviours the report lists, in its order. */
typedef enum {
    DRV_PIPELINED,        /* requests that arrived before the previous reply went out */
    DRV_QUEUED_OWN,       /* requests that waited behind the session's own (a timing profile) */
    DRV_QUEUED_OTHERS,    /* and behind another session's request or stream */
    DRV_POLLED_MOTION,    /* queries of a value while a motion ran */
    DRV_REFUSED,          /* error replies (ERR, an error status) */
    DRV_UNREAD_STREAM,    /* updates dropped: subscribed and not read */
    DRV_NO_GOODBYE,       /* streams closed without BYE or 0x07 */
    DRV_PARTIAL_AT_CLOSE, /* an unfinished line or frame at close */
    DRV_RECONNECT,        /* a session from an address whose earlier session had ended */
    DRV_FAST_STOP,        /* FAST STOPs caused: a close, a FASTSTOP command */
    DRV_BEHAVIOURS
} driver_behaviour_t;

/* One session's counts; also the sum over ended sessions (peaks: the
 * highest). */
typedef struct {
    uint32_t requests;
    uint32_t peak_per_second; /* the most requests in one second of simulated time */
    uint32_t most_in_flight;  /* the most whole requests that arrived together */
    uint32_t pipelined;
    uint32_t queued_behind_own; /* wsg_conn_waits(): 0 under the "ideal" timing */
    uint32_t queued_behind_others;
    uint32_t polls_in_motion;
    uint32_t errors[WSG_STATUS_COUNT];
    uint32_t subscriptions;
    unsigned long updates_dropped;
    uint32_t fast_stop_commands;
    uint32_t fast_stop_on_close;
    uint32_t closed_without_goodbye;
    uint32_t partial_at_close;
    uint32_t reconnects;
} driver_counts_t;

typedef struct driver_session {
    struct driver_session *next_in_bucket;
    list_node_t link; /* on the live list, oldest first */
    uint64_t id;
    unsigned device;
    wsg_transport_t transport;
    const char *protocol; /* "GCL", "binary", or NULL before the first message */
    char peer[DRIVER_PEER_MAX];
    uint64_t opened_us, first_request_us, last_request_us, closed_us;
    uint64_t second_ends_us; /* the end of the simulated second in_second counts */
    uint32_t in_second;      /* requests in it so far */
    uint32_t seen;           /* the connection's messages when its last read came */
    uint64_t read_us;        /* when its last read came */
    bool open;
    const char *close_reason; /* "announced", "dropped", "expired", "reset", "open at exit" */
    driver_counts_t counts;
} driver_session_t;

typedef struct {
    wsg_device_t *dev;      /* NULL: not attached */
    driver_session_t *last; /* the session of the last event (most come in runs) */
    driver_watch_t watch;
} driver_device_t;

struct driver_report {
    const driver_port_t *port;
    bool stopping;
    list_t live;
    driver_session_t *buckets[DRIVER_BUCKETS];
    unsigned live_count;
    unsigned long ended_count;
    driver_counts_t ended; /* the sum over every ended session */
    unsigned long ended_sessions_with[DRV_BEHAVIOURS];
    driver_session_t kept[DRIVER_ENDED_KEPT]; /* the last ended, a ring */
    unsigned kept_next;
    unsigned devices;
    driver_device_t device[];
};

/* Its error replies, all codes. */
unsigned long driver_counts_errors(const driver_counts_t *c);
/* How many of the session's counts show behaviour b (0: it did not). */
unsigned long driver_counts_of(const driver_counts_t *c, driver_behaviour_t b);
/* Adds part's counts to total (peaks: the highest). */
void driver_counts_add(driver_counts_t *total, const driver_counts_t *part);
/* A live session's counts as of now: its last read's requests and the
 * port's count of its dropped updates included. */
driver_counts_t driver_live_counts(const driver_report_t *r, const driver_session_t *s);

#endif
