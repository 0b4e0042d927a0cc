/* SPDX-License-Identifier: BSD-3-Clause */
#include "lan9118_netif.h"

#include "board.h"
#include "lan9118.h"
#include "lwip/etharp.h"
#include "lwip/pbuf.h"
#include "netif/ethernet.h"

#define MTU 1500u

/* Word-aligned bounce buffers: the FIFOs move 32-bit words, pbufs hold
 * bytes at any alignment. Only the main loop uses them. */
static uint32_t rx_frame[LAN9118_FRAME_MAX / 4u];
static uint32_t tx_frame[LAN9118_FRAME_MAX / 4u];

/* A locally administered address for a controller without an EEPROM. */
static const uint8_t fallback_mac[6] = {0x02, 0x57, 0x53, 0x47, 0x00, 0x14};

void Ethernet_Handler(void);
void Ethernet_Handler(void)
{
    lan9118_irq_ack();
    board_signal_event();
}

static err_t link_output(struct netif *netif, struct pbuf *p)
{
    (void)netif;
    if (p->tot_len > sizeof(tx_frame)) {
        return ERR_BUF;
    }
    (void)pbuf_copy_partial(p, tx_frame, p->tot_len, 0);
    return lan9118_tx(tx_frame, p->tot_len) ? ERR_OK : ERR_MEM;
}

err_t lan9118_netif_init(struct netif *netif)
{
    uint8_t mac[6];
    for (unsigned i = 0; i < sizeof(mac); i++) {
        mac[i] = fallback_mac[i];
    }
    if (!lan9118_init(mac)) {
        return ERR_IF;
    }
    netif->name[0] = 'e';
    netif->name[1] = 'n';
    netif->hwaddr_len = ETH_HWADDR_LEN;
    for (unsigned i = 0; i < ETH_HWADDR_LEN; i++) {
        netif->hwaddr[i] = mac[i];
    }
    netif->mtu = MTU;
    netif->flags = NETIF_FLAG_BROADCAST | NETIF_FLAG_ETHARP | NETIF_FLAG_ETHERNET;
    netif->output = etharp_output;
    netif->linkoutput = link_output;
    board_irq_enable(IRQ_ETHERNET);
    return ERR_OK;
}

static void deliver(struct netif *netif, size_t len)
{
    lan9118_rx_read(rx_frame);
    struct pbuf *p = pbuf_alloc(PBUF_RAW, (u16_t)len, PBUF_POOL);
    if (p == NULL) {
        return; /* out of buffers: the frame is lost, as on a busy wire */
    }
    (void)pbuf_take(p, rx_frame, (u16_t)len);
    if (netif->input(p, netif) != ERR_OK) {
        pbuf_free(p);
    }
}

bool lan9118_netif_poll(struct netif *netif)
{
    bool any = false;
    size_t len;
    while ((len = lan9118_rx_next()) > 0u) {
        deliver(netif, len);
        any = true;
    }
    return any;
}
