/* build/wsgsim: the virtual WSG gripper on a Linux host. */
#include <stdio.h>

#include "gripper.h"
#include "log.h"
#include "loop.h"
#include "options.h"
#include "simclock.h"
#include "tcp_server.h"
#include "udp_server.h"

#define EXIT_STARTUP_FAILED 2

static bool start_servers(const host_options_t *opts)
{
    if (opts->tcp_enabled &&
        !tcp_server_start(opts->bind_addr, opts->tcp_port, opts->max_clients)) {
        return false;
    }
    if (opts->udp_enabled && !udp_server_start(opts->bind_addr, opts->udp_port)) {
        return false;
    }
    return true;
}

static void announce(const host_options_t *opts)
{
    const wsg_device_t *dev = gripper_device();
    (void)dev;
    host_logf(HAL_LOG_INFO, "virtual %s ready: tcp %s:%d, udp %s:%d", opts->model, opts->bind_addr,
              tcp_server_port(), opts->bind_addr, udp_server_port());
}

int main(int argc, char **argv)
{
    host_options_t opts;
    options_result_t parsed = options_parse(argc, argv, &opts);
    if (parsed != OPTIONS_RUN) {
        return parsed == OPTIONS_EXIT_OK ? 0 : EXIT_STARTUP_FAILED;
    }
    setvbuf(stderr, NULL, _IOLBF, 0);
    simclock_init();
    loop_init();
    gripper_init(&opts);
    if (!start_servers(&opts)) {
        return EXIT_STARTUP_FAILED;
    }
    announce(&opts);
    while (!loop_stop_requested()) {
        uint64_t deadline = gripper_tick();
        loop_wait(deadline);
        gripper_tick();
        tcp_server_reap();
        udp_server_reap();
    }
    host_logf(HAL_LOG_INFO, "shutting down");
    tcp_server_stop();
    udp_server_stop();
    return 0;
}
