/* SPDX-License-Identifier: BSD-3-Clause */
#include "observers.h"

#include "bin_coverage.h"
#include "coverage.h"
#include "record.h"
#include "trace.h"
#include "web/web_lines.h"
#include "wsg/wsg_gcl.h"

static struct {
    bool trace;
    bool record;
    bool coverage; /* --coverage, or a control channel that may ask for it */
    bool strict;
    web_lines_t *web_lines; /* the web server's, NULL when it is off */
} hub;

static void on_message_in(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)ctx;
    if (hub.coverage) {
        coverage_line_in(c);
    }
    if (hub.trace) {
        trace_line(c, '<', line, len);
    }
    record_gcl(c, '<', line, len); /* nothing unless a record is open */
    web_lines_note(hub.web_lines, c, true, line, len);
}

static void on_message_out(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)ctx;
    if (hub.coverage) {
        bin_coverage_frame_out((const unsigned char *)line, len);
    }
    if (hub.trace) {
        trace_line(c, '>', line, len);
    }
    record_gcl(c, '>', line, len);
    web_lines_note(hub.web_lines, c, false, line, len);
}

/* Coverage without a trace (the control channel's case): nothing to ask per
 * message. A record opened without --record (the simulation control tests
 * open one) is still written, and the web page's lines still kept. */
static void on_message_in_coverage(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)ctx;
    coverage_line_in(c);
    record_gcl(c, '<', line, len);
    web_lines_note(hub.web_lines, c, true, line, len);
}

static void on_message_out_coverage(void *ctx, const wsg_conn_t *c, const char *line, size_t len)
{
    (void)ctx;
    bin_coverage_frame_out((const unsigned char *)line, len);
    record_gcl(c, '>', line, len);
    web_lines_note(hub.web_lines, c, false, line, len);
}

static void on_grip_state(void *ctx, wsg_grip_state_t from, wsg_grip_state_t to)
{
    (void)ctx;
    coverage_grip(from, to);
}

static void on_command_done(void *ctx, const wsg_conn_t *c, const char *name, int index,
                            unsigned form, unsigned argc, wsg_status_t status)
{
    (void)ctx;
    (void)c;
    coverage_command(name, index, form, argc, status);
}

static void on_error_sent(void *ctx, const wsg_conn_t *c, int index, wsg_status_t status)
{
    (void)ctx;
    (void)c;
    coverage_error(index, status);
}

static void on_tolerated(void *ctx, const wsg_conn_t *c, const char *name, const char *what)
{
    (void)ctx;
    if (hub.coverage) {
        coverage_tolerated(c, name, what);
    }
    if (hub.strict && hub.trace) {
        trace_tolerated(c, name, what);
    }
}

static const wsg_conn_observer_t message_observer = {
    .message_in = on_message_in,
    .message_out = on_message_out,
};

static const wsg_conn_observer_t coverage_message_observer = {
    .message_in = on_message_in_coverage,
    .message_out = on_message_out_coverage,
};

static const wsg_device_observer_t device_observer = {
    .grip_state_changed = on_grip_state,
};

static const wsg_gcl_observer_t coverage_observer = {
    .command_done = on_command_done,
    .error_sent = on_error_sent,
    .tolerated = on_tolerated,
};

/* Strict tracing without coverage still hears tolerated input. */
static const wsg_gcl_observer_t tolerated_observer = {
    .tolerated = on_tolerated,
};

void simctl_observers_attach(wsg_device_t *dev, const host_options_t *opts)
{
    hub.trace = opts->trace;
    hub.record = opts->record_path != NULL;
    hub.coverage = opts->coverage_path != NULL || opts->sim_port >= 0;
    hub.strict = opts->strict;
    hub.web_lines = opts->web_lines;
    const wsg_conn_observer_t *messages = NULL;
    if (hub.coverage && !hub.trace) {
        messages = &coverage_message_observer;
    } else if (hub.trace || hub.record || hub.coverage || hub.web_lines != NULL) {
        messages = &message_observer;
    }
    wsg_conn_observe(dev, messages, NULL);
    wsg_device_observe(dev, hub.coverage ? &device_observer : NULL, NULL);
    const wsg_gcl_observer_t *gcl = hub.coverage              ? &coverage_observer
                                    : hub.strict && hub.trace ? &tolerated_observer
                                                              : NULL;
    wsg_gcl_observe(dev, gcl, NULL);
}

void simctl_observers_detach(wsg_device_t *dev)
{
    wsg_conn_observe(dev, NULL, NULL);
    wsg_device_observe(dev, NULL, NULL);
    wsg_gcl_observe(dev, NULL, NULL);
}

void simctl_observers_after_tick(wsg_device_t *dev)
{
    if (hub.coverage) {
        coverage_flags(wsg_device_flags(dev));
    }
}

bool simctl_observers_strict(void)
{
    return hub.strict;
}
