#include "simctl_hooks.h"

#include "coverage.h"
#include "record.h"
#include "trace.h"

static struct {
    bool trace;
    bool strict;
} hub;

static void on_line_in(void *ctx, const wsg_session_t *s, const char *line, size_t len)
{
    (void)ctx;
    coverage_line_in(s);
    if (hub.trace) {
        trace_device_hooks()->line_in(NULL, s, line, len);
    }
    record_gcl(s, '<', line, len);
}

static void on_line_out(void *ctx, const wsg_session_t *s, const char *line, size_t len)
{
    (void)ctx;
    if (hub.trace) {
        trace_device_hooks()->line_out(NULL, s, line, len);
    }
    record_gcl(s, '>', line, len);
    coverage_line_out(line, len);
}

static void on_grip_state(void *ctx, wsg_grip_state_t from, wsg_grip_state_t to)
{
    (void)ctx;
    coverage_grip(from, to);
}

static void on_command_done(void *ctx, const wsg_session_t *s, const char *name, unsigned form,
                            unsigned argc, wsg_status_t status)
{
    (void)ctx;
    (void)s;
    coverage_command(name, form, argc, status);
}

static void on_tolerated(void *ctx, const wsg_session_t *s, const char *name, const char *what)
{
    (void)ctx;
    coverage_tolerated(s, name, what);
    if (hub.strict && hub.trace) {
        trace_tolerated(s, name, what);
    }
}

static const wsg_device_hooks_t hub_hooks = {
    .line_in = on_line_in,
    .line_out = on_line_out,
    .grip_state_changed = on_grip_state,
    .command_done = on_command_done,
    .tolerated = on_tolerated,
};

void simctl_hooks_attach(wsg_device_t *dev, bool trace, bool strict)
{
    hub.trace = trace;
    hub.strict = strict;
    wsg_device_set_hooks(dev, &hub_hooks, NULL);
}

bool simctl_hooks_strict(void)
{
    return hub.strict;
}

void simctl_hooks_after_step(const wsg_device_t *dev)
{
    coverage_flags(dev->flags);
}
