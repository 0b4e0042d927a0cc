/* SPDX-License-Identifier: BSD-3-Clause */
/* The driver report's outputs: the "driver" section of the coverage
 * report (and DRIVER?) and the human summary at exit. Each behaviour says
 * what a real gripper does with it; docs/behaviour.md gives the sources. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "driver_report_internal.h"
#include "wsg/wsg_names.h"

typedef struct {
    const char *key;   /* the JSON name */
    const char *label; /* the summary's words for the count */
    const char *real;  /* what the real device does with it */
} behaviour_text_t;

static const behaviour_text_t behaviours[DRV_BEHAVIOURS] = {
    [DRV_PIPELINED] = {"pipelined", "requests sent before the previous reply",
                       "the device's command processor takes them in order, one at a time (a GCL "
                       "query about 15 ms): each waits for those before it"},
    [DRV_QUEUED_OWN] =
        {"queued_behind_own", "requests queued behind the client's own",
         "the command processor serves one request at a time, each for its "
         "service time (a GCL query about 15 ms, give or take 3): a request sent before the "
         "reply to the one before waits for it, and so does its reply"},
    [DRV_QUEUED_OTHERS] = {"queued_behind_others",
                           "requests queued behind other clients' (or their streams)",
                           "the device has one command processor for all its connections and "
                           "interfaces: another client's requests and auto-update streams take "
                           "their turns first, each about 15 ms"},
    [DRV_POLLED_MOTION] = {"polled_during_motion", "queries polled during a motion",
                           "each query occupies the command processor for its service time and "
                           "delays the STOP or FIN behind it; AUTOSEND or an auto-update stream "
                           "delivers the value without it"},
    [DRV_REFUSED] = {"refused", "commands refused or failed (error replies)",
                     "the device refuses the same commands with the same codes: busy "
                     "(E_ALREADY_RUNNING), not homed (E_NOT_INITIALIZED), FAST STOP "
                     "(E_ACCESS_DENIED until acknowledged), out of range"},
    [DRV_UNREAD_STREAM] = {"unread_stream_updates", "stream updates dropped, not read",
                           "the device keeps sending: the socket's buffers fill and the values "
                           "the client reads when it resumes are old ones"},
    [DRV_NO_GOODBYE] = {"closed_without_goodbye", "sessions closed without BYE or 0x07",
                        "an unannounced close raises FAST STOP (unless the device is set "
                        "otherwise): motion is refused until FSACK or 0x24"},
    [DRV_PARTIAL_AT_CLOSE] = {"partial_at_close", "sessions closed inside a line or frame",
                              "the unfinished command is discarded, it never ran"},
    [DRV_RECONNECT] = {"reconnects", "reconnects (an address returning)",
                       "each is a new connection; after an unannounced close the device "
                       "still holds FAST STOP"},
    [DRV_FAST_STOP] = {"fast_stops_caused", "FAST STOPs caused (closes, FASTSTOP commands)",
                       "FAST STOP stops the fingers at once and refuses motion until "
                       "acknowledged"},
};

/* What the device's pace makes of a session's peak rate: one request at a
 * time, a GCL query in about 15 ms (docs/behaviour.md). */
#define REAL_REQUESTS_PER_SECOND 66u
static const char real_pace[] = "the device serves one request at a time, a GCL query in about "
                                "15 ms: some 66 a second, more wait";

/* What an error code says of the refusal. */
static const char *refusal_reason(unsigned code)
{
    switch (code) {
    case E_ALREADY_RUNNING:
        return "busy: a motion runs";
    case E_NOT_INITIALIZED:
        return "not homed";
    case E_ACCESS_DENIED:
        return "FAST STOP or not allowed now";
    case E_RANGE_ERROR:
    case E_INVALID_PARAMETER:
    case E_INDEX_OUT_OF_BOUNDS:
        return "out of range";
    case E_CMD_UNKNOWN:
    case E_CMD_FORMAT_ERROR:
    case E_NOT_ENOUGH_PARAMS:
    case E_NO_PARAM_EXPECTED:
    case E_CHECKSUM_ERROR:
        return "malformed";
    case E_CMD_ABORTED:
        return "aborted by a STOP or a newer command";
    case E_AXIS_BLOCKED:
        return "axis blocked";
    case E_TIMEOUT:
        return "timed out";
    default:
        return "failed";
    }
}

/* Every session's counts, and how many sessions showed each behaviour. */
static driver_counts_t all_counts(const driver_report_t *r, unsigned long with[DRV_BEHAVIOURS])
{
    driver_counts_t total = r->ended;
    memcpy(with, r->ended_sessions_with, sizeof(r->ended_sessions_with));
    LIST_EACH (node, &r->live) {
        driver_counts_t c = driver_live_counts(r, LIST_ITEM(node, driver_session_t, link));
        driver_counts_add(&total, &c);
        for (unsigned b = 0; b < DRV_BEHAVIOURS; b++) {
            with[b] += driver_counts_of(&c, (driver_behaviour_t)b) > 0 ? 1u : 0u;
        }
    }
    return total;
}

static cJSON *errors_json(const driver_counts_t *c)
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned code = 1; code < WSG_STATUS_COUNT; code++) {
        if (c->errors[code] == 0) {
            continue;
        }
        cJSON *item = cJSON_CreateObject();
        cJSON_AddNumberToObject(item, "code", code);
        cJSON_AddStringToObject(item, "name", wsg_status_name((wsg_status_t)code));
        cJSON_AddStringToObject(item, "why", refusal_reason(code));
        cJSON_AddNumberToObject(item, "count", c->errors[code]);
        cJSON_AddItemToArray(list, item);
    }
    return list;
}

static void add_counts_json(cJSON *o, const driver_counts_t *c)
{
    cJSON_AddNumberToObject(o, "requests", c->requests);
    cJSON_AddNumberToObject(o, "peak_requests_per_second", c->peak_per_second);
    cJSON_AddNumberToObject(o, "most_in_flight", c->most_in_flight);
    cJSON_AddNumberToObject(o, "pipelined", c->pipelined);
    cJSON_AddNumberToObject(o, "queued_behind_own", c->queued_behind_own);
    cJSON_AddNumberToObject(o, "queued_behind_others", c->queued_behind_others);
    cJSON_AddNumberToObject(o, "polled_during_motion", c->polls_in_motion);
    cJSON_AddNumberToObject(o, "error_replies", (double)driver_counts_errors(c));
    cJSON_AddItemToObject(o, "errors", errors_json(c));
    cJSON_AddNumberToObject(o, "subscriptions", c->subscriptions);
    cJSON_AddNumberToObject(o, "unread_stream_updates", (double)c->updates_dropped);
    cJSON_AddNumberToObject(o, "fast_stop_commands", c->fast_stop_commands);
    cJSON_AddNumberToObject(o, "fast_stop_on_close", c->fast_stop_on_close);
    cJSON_AddNumberToObject(o, "closed_without_goodbye", c->closed_without_goodbye);
    cJSON_AddNumberToObject(o, "partial_at_close", c->partial_at_close);
    cJSON_AddNumberToObject(o, "reconnects", c->reconnects);
}

static cJSON *session_json(const driver_report_t *r, const driver_session_t *s)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "session", (double)s->id);
    cJSON_AddNumberToObject(o, "device", s->device);
    cJSON_AddStringToObject(o, "transport",
                            s->transport == WSG_TRANSPORT_DATAGRAM ? "udp"
                            : s->transport == WSG_TRANSPORT_SERIAL ? "serial"
                                                                   : "tcp");
    cJSON_AddStringToObject(o, "protocol", s->protocol != NULL ? s->protocol : "none");
    cJSON_AddStringToObject(o, "peer", s->peer);
    cJSON_AddBoolToObject(o, "open", s->open);
    if (!s->open) {
        cJSON_AddStringToObject(o, "closed", s->close_reason);
    }
    cJSON_AddNumberToObject(o, "opened_us", (double)s->opened_us);
    uint64_t span = s->last_request_us - s->first_request_us;
    cJSON_AddNumberToObject(o, "requests_span_us", (double)span);
    /* the mean rate over the span of its requests (none within one instant) */
    cJSON_AddNumberToObject(o, "requests_per_second",
                            span > 0 ? (double)(s->counts.requests - 1u) * 1e6 / (double)span : 0);
    driver_counts_t c = s->open ? driver_live_counts(r, s) : s->counts;
    add_counts_json(o, &c);
    return o;
}

static cJSON *sessions_json(const driver_report_t *r)
{
    cJSON *list = cJSON_CreateArray();
    unsigned kept =
        r->ended_count < DRIVER_ENDED_KEPT ? (unsigned)r->ended_count : DRIVER_ENDED_KEPT;
    for (unsigned i = 0; i < kept; i++) {
        /* oldest first: the ring's next slot is the oldest once it is full */
        unsigned at = (r->kept_next + DRIVER_ENDED_KEPT - kept + i) % DRIVER_ENDED_KEPT;
        cJSON_AddItemToArray(list, session_json(r, &r->kept[at]));
    }
    LIST_EACH (node, &r->live) {
        cJSON_AddItemToArray(list, session_json(r, LIST_ITEM(node, driver_session_t, link)));
    }
    return list;
}

static cJSON *behaviours_json(const driver_counts_t *total, const unsigned long with[])
{
    cJSON *list = cJSON_CreateArray();
    for (unsigned b = 0; b < DRV_BEHAVIOURS; b++) {
        cJSON *item = cJSON_CreateObject();
        cJSON_AddStringToObject(item, "behaviour", behaviours[b].key);
        cJSON_AddNumberToObject(item, "count",
                                (double)driver_counts_of(total, (driver_behaviour_t)b));
        cJSON_AddNumberToObject(item, "sessions", (double)with[b]);
        cJSON_AddStringToObject(item, "real_gripper", behaviours[b].real);
        cJSON_AddItemToArray(list, item);
    }
    return list;
}

cJSON *driver_report_json(const driver_report_t *r)
{
    unsigned long with[DRV_BEHAVIOURS];
    driver_counts_t total = all_counts(r, with);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "sessions", (double)(r->ended_count + r->live_count));
    cJSON_AddNumberToObject(root, "open_sessions", r->live_count);
    cJSON_AddNumberToObject(root, "ended_sessions", (double)r->ended_count);
    cJSON_AddNumberToObject(root, "ended_sessions_listed",
                            r->ended_count < DRIVER_ENDED_KEPT ? (double)r->ended_count
                                                               : DRIVER_ENDED_KEPT);
    cJSON *all = cJSON_AddObjectToObject(root, "total");
    add_counts_json(all, &total);
    cJSON *pace = cJSON_AddObjectToObject(root, "pace");
    cJSON_AddNumberToObject(pace, "peak_requests_per_second", total.peak_per_second);
    cJSON_AddNumberToObject(pace, "real_gripper_requests_per_second", REAL_REQUESTS_PER_SECOND);
    cJSON_AddStringToObject(pace, "real_gripper", real_pace);
    cJSON_AddItemToObject(root, "behaviours", behaviours_json(&total, with));
    cJSON_AddItemToObject(root, "session_list", sessions_json(r));
    return root;
}

/* ---- the human summary ---- */

typedef struct {
    char *text;
    size_t len, cap;
} text_t;

static void addf(text_t *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void addf(text_t *t, const char *fmt, ...)
{
    va_list ap;
    for (;;) {
        va_start(ap, fmt);
        int n = vsnprintf(t->text != NULL ? t->text + t->len : NULL,
                          t->text != NULL ? t->cap - t->len : 0, fmt, ap);
        va_end(ap);
        if (n < 0) {
            return;
        }
        if (t->text != NULL && t->len + (size_t)n < t->cap) {
            t->len += (size_t)n;
            return;
        }
        size_t cap = (t->cap + (size_t)n + 1u) * 2u;
        char *grown = realloc(t->text, cap);
        if (grown == NULL) {
            return;
        }
        t->text = grown;
        t->cap = cap;
    }
}

static void add_refusals(text_t *t, const driver_counts_t *c)
{
    for (unsigned code = 1; code < WSG_STATUS_COUNT; code++) {
        if (c->errors[code] > 0) {
            addf(t, "    %u %s (%s)\n", c->errors[code], wsg_status_name((wsg_status_t)code),
                 refusal_reason(code));
        }
    }
}

char *driver_report_text(const driver_report_t *r)
{
    unsigned long with[DRV_BEHAVIOURS];
    driver_counts_t total = all_counts(r, with);
    text_t t = {0};
    addf(&t,
         "driver report: %lu sessions (%u open), %u requests, peak %u per simulated second, "
         "most in flight %u, %u subscriptions\n",
         r->ended_count + r->live_count, r->live_count, total.requests, total.peak_per_second,
         total.most_in_flight, total.subscriptions);
    if (total.peak_per_second > REAL_REQUESTS_PER_SECOND) {
        addf(&t, "  peak above a real gripper's pace: %s\n", real_pace);
    }
    for (unsigned b = 0; b < DRV_BEHAVIOURS; b++) {
        unsigned long count = driver_counts_of(&total, (driver_behaviour_t)b);
        addf(&t, "  %s: %lu in %lu sessions%s%s\n", behaviours[b].label, count, with[b],
             count > 0 ? "; a real gripper: " : "", count > 0 ? behaviours[b].real : "");
        if (b == DRV_REFUSED) {
            add_refusals(&t, &total);
        }
    }
    return t.text;
}
