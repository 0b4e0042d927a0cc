/* SPDX-License-Identifier: BSD-3-Clause */
/* The running wsgsim: every instance host/main.c creates and wires, one
 * member per line, grouped by layer (lower layers first). Calls point down:
 * a module gets pointers to the lower-layer instances it needs when it is
 * started, and upper layers attach to lower ones with observers. */
#ifndef HOST_HOST_H
#define HOST_HOST_H

#include "can_log.h"
#include "fleet.h"
#include "loop.h"
#include "net.h"
#include "options.h"
#include "simctl/control.h"
#include "web/web_server.h"

typedef struct host {
    const host_options_t *opts; /* what the command line and --config asked for */
    /* OS layer */
    host_loop_t *loop; /* the event loop every socket is watched on */
    net_t net;         /* the server's own listening sockets */
    can_log_t can_log; /* --can-log: the in-process bus's frames */
    /* port layer */
    fleet_t *fleet; /* the devices and their servers and finger buses */
    /* diagnostics: trace, record and coverage are created in main.c only
     * when asked for, and attached to each device by a fleet observer */
    /* simulation control */
    simctl_t *sim; /* clock, scheduler, scenario, faults, --sim-port */
    /* web */
    web_server_t *web; /* --http-port */
} host_t;

#endif
