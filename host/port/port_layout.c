/* SPDX-License-Identifier: BSD-3-Clause */
#include "port_layout.h"

#define PORT_MAX 65535L

bool port_layout_paired(const port_plan_t *plan)
{
    return plan->binary_base == PORT_LAYOUT_BINARY_DEFAULT &&
           plan->reply_base == PORT_LAYOUT_REPLY_DEFAULT;
}

/* Where the pairs start: 1500, unless the GCL UDP ports [udp, udp + N)
 * reach into [1500, 1500 + 2N); then just past them. */
static long first_pair(const port_plan_t *plan)
{
    long n = (long)plan->devices;
    long pairs = PORT_LAYOUT_BINARY_DEFAULT;
    long udp = plan->udp_base;
    bool gcl_range = plan->udp_enabled && udp != 0;
    if (gcl_range && udp < pairs + 2 * n && pairs < udp + n) {
        return udp + n;
    }
    return pairs;
}

static long offset_port(int base, unsigned i)
{
    return base == 0 ? 0 : (long)base + (long)i;
}

bool port_layout_of(const port_plan_t *plan, unsigned i, port_layout_t *out)
{
    long tcp = offset_port(plan->tcp_base, i);
    long udp = offset_port(plan->udp_base, i);
    long binary = offset_port(plan->binary_base, i);
    long reply = offset_port(plan->reply_base, i);
    if (port_layout_paired(plan)) {
        binary = first_pair(plan) + 2L * (long)i;
        reply = binary + 1;
    }
    *out = (port_layout_t){tcp, udp, binary, reply};
    return tcp <= PORT_MAX && udp <= PORT_MAX && binary <= PORT_MAX && reply <= PORT_MAX;
}
