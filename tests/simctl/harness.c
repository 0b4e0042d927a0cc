/* SPDX-License-Identifier: BSD-3-Clause */
#include "harness.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "coverage.h"
#include "fleet.h"
#include "hal_clock.h"
#include "loop.h"
#include "net.h"
#include "options.h"
#include "clock.h"
#include "simctl/commands.h"
#include "simctl/control.h"

h_client_t t_gcl;
simctl_t *t_sim;
fleet_t *t_fleet;
static char *last_reply;
static host_options_t opts; /* the fleet's, for as long as it runs */
/* What a fleet needs below it; the tests' device has no sockets. */
static host_loop_t *loop;
static net_t net;

static coverage_t *t_coverage; /* counted on every device, as with a control channel */

/* As build/wsgsim does: every device counts for the coverage. */
static void attach_observers(void *ctx, gripper_t *g)
{
    (void)ctx;
    coverage_attach(t_coverage, &g->device, g->index);
}

/* ... and samples its flags after each control step that changed them. */
static void sample_coverage(void *ctx, gripper_t *g)
{
    (void)ctx;
    coverage_sample_flags(t_coverage, g->index);
}

static void setup_with(int argc, char **argv)
{
    static fleet_observer_t observers = {
        .device_started = attach_observers, .flags_changed = sample_coverage, .ctx = &opts};
    ck_assert_int_eq(options_parse(argc, argv, &opts), OPTIONS_RUN);
    t_sim = simctl_create();
    ck_assert_ptr_nonnull(t_sim);
    simclock_start_paused(simctl_clock(t_sim));
    opts.sim_port = 0;        /* the tests drive the control channel: coverage is observed */
    opts.tcp_enabled = false; /* one device, no sockets: the tests feed it */
    opts.udp_enabled = false;
    t_coverage = coverage_create(opts.strict, (unsigned)opts.devices);
    ck_assert_ptr_nonnull(t_coverage);
    simctl_set_diagnostics(t_sim, NULL, t_coverage);
    loop = loop_create();
    ck_assert_ptr_nonnull(loop);
    net_init(&net);
    t_fleet = fleet_create(loop, &net);
    ck_assert_ptr_nonnull(t_fleet);
    fleet_observe(t_fleet, &observers);
    simctl_set_fleet(t_sim, t_fleet);
    ck_assert(fleet_start(t_fleet, &opts));
    t_reopen();
}

void t_setup(void)
{
    static char *argv[] = {"wsgsim", NULL};
    setup_with(1, argv);
}

void t_setup_three_devices(void)
{
    static char *argv[] = {"wsgsim", "--devices", "3", NULL};
    setup_with(3, argv);
}

void t_reinit(const host_options_t *with)
{
    gripper_t *g = fleet_gripper(t_fleet, 0);
    gripper_touched_t *touched = g->touched_list;
    struct script_guard *guard = g->script_guard;
    gripper_release(g);
    ck_assert(gripper_init(g, loop, with, 0, touched, guard));
    attach_observers((void *)with, g);
    gripper_start(g);
}

void t_reopen(void)
{
    h_open_on(&t_gcl, &fleet_gripper(t_fleet, 0)->device, &wsg_gcl_driver, WSG_TRANSPORT_STREAM);
}

void t_setup_homed(void)
{
    t_setup();
    GCL_EQ("HOME()", "ACK HOME");
    ck_assert_int_ge(t_until("FIN HOME", 5000), 0);
}

void t_teardown(void)
{
    ck_assert_msg(!t_gcl.bad_line, "the GCL session got something that is not one whole line");
    for (unsigned i = 0; i < fleet_count(t_fleet); i++) {
        simctl_delay_clear_all(simctl_delays(t_sim), &fleet_gripper(t_fleet, i)->device, false);
    }
    fleet_destroy(t_fleet);
    t_fleet = NULL;
    simctl_set_diagnostics(t_sim, NULL, NULL);
    coverage_destroy(t_coverage);
    t_coverage = NULL;
    loop_destroy(loop);
    loop = NULL;
    simctl_destroy(t_sim);
    t_sim = NULL;
    free(last_reply);
    last_reply = NULL;
}

const char *ctl(const char *line)
{
    free(last_reply);
    last_reply = simctl_exec(t_sim, line, strlen(line), NULL, NULL);
    ck_assert_ptr_nonnull(last_reply);
    return last_reply;
}

const char *ctl_on(unsigned device, const char *line)
{
    unsigned selected = device;
    simctl_outcome_t outcome = {false, false};
    free(last_reply);
    last_reply = simctl_exec(t_sim, line, strlen(line), &selected, &outcome);
    ck_assert_ptr_nonnull(last_reply); /* no STEP here: nothing is deferred */
    return last_reply;
}

uint32_t t_device_flags(unsigned device)
{
    ck_assert_uint_lt(device, fleet_count(t_fleet));
    return wsg_device_flags(&fleet_gripper(t_fleet, device)->device);
}

int t_err_code(const char *reply)
{
    char name[32];
    int code = -1;
    if (sscanf(reply, "ERR %31s %d", name, &code) != 2) {
        return -1;
    }
    return code;
}

size_t gcl_unread(void)
{
    return h_unread(&t_gcl);
}

const char *gcl_next(void)
{
    return h_next_line(&t_gcl);
}

const char *gcl(const char *line)
{
    char buf[512];
    size_t len = strlen(line);
    ck_assert_uint_lt(len + 1, sizeof(buf));
    memcpy(buf, line, len);
    buf[len] = '\n';
    size_t before = t_gcl.count;
    gripper_feed(fleet_gripper(t_fleet, 0), &t_gcl.conn, (const uint8_t *)buf, len + 1, 0);
    return t_gcl.count > before ? gcl_next() : "<no reply>";
}

void t_step_ms(double ms)
{
    char line[64];
    snprintf(line, sizeof(line), "STEP(%g)", ms);
    const char *reply = ctl(line);
    ck_assert_msg(strncmp(reply, "STEP=", 5) == 0, "%s -> %s", line, reply);
}

int t_until(const char *text, int timeout_ms)
{
    for (int waited = 0; waited <= timeout_ms; waited++) {
        while (gcl_unread() > 0) {
            if (strcmp(gcl_next(), text) == 0) {
                return waited;
            }
        }
        t_step_ms(1);
    }
    return -1;
}

int t_flag(int bit)
{
    char query[32];
    char expect[40];
    snprintf(query, sizeof(query), "SYSFLAGS[%d]?", bit);
    snprintf(expect, sizeof(expect), "SYSFLAGS[%d]=", bit);
    const char *reply = gcl(query);
    size_t n = strlen(expect);
    return strncmp(reply, expect, n) == 0 ? reply[n] - '0' : -1;
}

int t_gripstate(void)
{
    int state = -1;
    return sscanf(gcl("GRIPSTATE?"), "GRIPSTATE=%d", &state) == 1 ? state : -1;
}

uint64_t t_now_us(void)
{
    return hal_clock_now_us();
}

const char *t_temp_file(const char *text)
{
    static char path[64];
    snprintf(path, sizeof(path), "/tmp/simctl_test_XXXXXX");
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    size_t len = strlen(text);
    ck_assert_int_eq(write(fd, text, len), (ssize_t)len);
    close(fd);
    return path;
}

const char *t_capture_stderr(bool (*fn)(void *), void *arg, bool *result)
{
    static char text[4096];
    fflush(stderr);
    FILE *tmp = tmpfile();
    ck_assert_ptr_nonnull(tmp);
    int saved = dup(fileno(stderr));
    dup2(fileno(tmp), fileno(stderr));
    *result = fn(arg);
    fflush(stderr);
    dup2(saved, fileno(stderr));
    close(saved);
    rewind(tmp);
    size_t n = fread(text, 1, sizeof(text) - 1, tmp);
    text[n] = '\0';
    fclose(tmp);
    return text;
}
