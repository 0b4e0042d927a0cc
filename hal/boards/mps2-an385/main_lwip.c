/* SPDX-License-Identifier: BSD-3-Clause */
/* The Ethernet image (stage 2 of the board port): GCL on TCP 1000 and
 * UDP 1000 through lwIP on the LAN9118, and on UART0 as in the serial image;
 * the binary protocol on TCP 1000 (first byte 0xAA), UDP 1500 (replies to
 * port 1501) and UART0. The board takes the manual's factory address,
 * 192.168.1.20/24. */
#include "app.h"
#include "board.h"
#include "gcl_tcp.h"
#include "hal_log.h"
#include "lan9118_netif.h"
#include "lwip/init.h"
#include "lwip/netif.h"
#include "lwip/timeouts.h"
#include "lwip_udp.h"
#include "netif/ethernet.h"
#include "serial_port.h"
#include "web_status.h"
#include "wsg/wsg_bin.h"

#define GCL_PORT 1000u
#define BINARY_UDP_PORT 1500u
#define BINARY_UDP_REPLY_PORT 1501u

/* A TCP connection's first byte chooses: the binary preamble, else GCL. */
static const wsg_proto_driver_t *const drivers[] = {&wsg_bin_driver, &wsg_gcl_driver};

static struct netif eth;

/* The UDP servers: GCL and the binary protocol, peers in static pools. */
static lwip_udp_server_t gcl_udp;
static wsg_peer_t gcl_udp_peers[LWIP_UDP_GCL_PEERS];
static lwip_udp_server_t binary_udp;
static wsg_peer_t binary_udp_peers[LWIP_UDP_BINARY_PEERS];

static bool udp_servers_start(void)
{
    return lwip_udp_start(&gcl_udp, &wsg_gcl_driver, GCL_PORT, 0, gcl_udp_peers,
                          LWIP_UDP_GCL_PEERS) &&
           lwip_udp_start(&binary_udp, &wsg_bin_driver, BINARY_UDP_PORT, BINARY_UDP_REPLY_PORT,
                          binary_udp_peers, LWIP_UDP_BINARY_PEERS);
}

static void udp_servers_poll(void)
{
    lwip_udp_poll(&gcl_udp);
    lwip_udp_poll(&binary_udp);
}

static bool network_init(void)
{
    ip4_addr_t addr, mask, gateway;
    IP4_ADDR(&addr, 192, 168, 1, 20);
    IP4_ADDR(&mask, 255, 255, 255, 0);
    ip4_addr_set_zero(&gateway); /* GCL clients share the subnet */
    lwip_init();
    if (netif_add(&eth, &addr, &mask, &gateway, NULL, lan9118_netif_init, ethernet_input) == NULL) {
        hal_log(HAL_LOG_ERROR, "lwip: no LAN9118 found, serial GCL only");
        return false;
    }
    netif_set_default(&eth);
    netif_set_up(&eth);
    netif_set_link_up(&eth);
    if (!gcl_tcp_init(GCL_PORT) || !udp_servers_start()) {
        hal_log(HAL_LOG_ERROR, "lwip: cannot listen on ports 1000 and 1500");
        return false;
    }
    web_status_init();
    return true;
}

int main(void)
{
    board_clock_init();
    board_log_init();
    app_init(drivers, sizeof(drivers) / sizeof(drivers[0]));
    serial_port_init();
    bool network = network_init();
    hal_log(HAL_LOG_INFO, network ? "wsgsim mps2-an385 lwIP image: GCL on 192.168.1.20 TCP 1000, "
                                    "UDP 1000 and UART0, binary UDP 1500, ready"
                                  : "wsgsim mps2-an385 lwIP image: no network");
    for (;;) {
        serial_port_poll();
        if (network) {
            (void)lan9118_netif_poll(&eth);
            sys_check_timeouts();
            gcl_tcp_poll();
            udp_servers_poll();
        }
        app_poll();
        board_sleep();
    }
}
