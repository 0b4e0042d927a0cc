/* SPDX-License-Identifier: BSD-3-Clause */
/* The ports of a fleet's devices (--devices N): device i's GCL TCP and UDP
 * ports, binary UDP port and binary reply port, from the configured bases.
 * With the default binary ports the layout never collides, for any N. */
#ifndef HOST_PORT_LAYOUT_H
#define HOST_PORT_LAYOUT_H

#include <stdbool.h>

#define PORT_LAYOUT_BINARY_DEFAULT 1500
#define PORT_LAYOUT_REPLY_DEFAULT 1501

typedef struct {
    int tcp_base, udp_base;      /* 0: a free port each */
    int binary_base, reply_base; /* binary 0: off; reply 0: the sender's own port */
    bool udp_enabled;            /* false: no GCL UDP range to keep clear of */
    unsigned devices;
} port_plan_t;

typedef struct {
    long tcp, udp;      /* 0: a free port */
    long binary, reply; /* binary 0: off */
} port_layout_t;

/* True when the binary ports are the defaults (1500 and 1501): device i
 * then takes the pair (P + 2i, P + 2i + 1), P being 1500, or the first
 * port past the GCL UDP ports when those reach into the pairs. Otherwise
 * device i takes (binary + i, reply + i), as configured. */
bool port_layout_paired(const port_plan_t *plan);
/* Device i's ports; false when one of them would pass 65535 (*out holds
 * them all the same, for the error). */
bool port_layout_of(const port_plan_t *plan, unsigned i, port_layout_t *out);

#endif
