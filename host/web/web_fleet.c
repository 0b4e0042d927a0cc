/* SPDX-License-Identifier: BSD-3-Clause */
/* The devices the web serves (web_server_set_fleet): set by main, asked by
 * the routes. A leaf, so that no route module calls back into another for
 * it. Glue until the web server is an instance of its own that is handed
 * the fleet when created. */
#include "web/web_internal.h"
#include "web/web_server.h"

static struct fleet *devices;

void web_server_set_fleet(struct fleet *fleet)
{
    devices = fleet;
}

struct fleet *web_fleet(void)
{
    return devices;
}
