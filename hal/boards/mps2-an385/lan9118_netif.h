/* SPDX-License-Identifier: BSD-3-Clause */
/* lwIP network interface over the LAN9118. */
#ifndef LAN9118_NETIF_H
#define LAN9118_NETIF_H

#include <stdbool.h>

#include "lwip/netif.h"

/* netif_add() init callback: finds the controller and sets the interface up
 * as an Ethernet with ARP. */
err_t lan9118_netif_init(struct netif *netif);

/* Hands every received frame to lwIP; true if there was any. */
bool lan9118_netif_poll(struct netif *netif);

#endif
