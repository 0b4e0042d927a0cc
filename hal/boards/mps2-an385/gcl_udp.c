/* SPDX-License-Identifier: BSD-3-Clause */
#include "gcl_udp.h"

#include <string.h>

#include "app.h"
#include "hal_log.h"
#include "lwip/sys.h"
#include "lwip/udp.h"

/* UDP has no connection to lose: a peer that stays silent this long (and
 * has no AUTOSEND running) is forgotten, freeing its session. */
#define PEER_IDLE_MS 300000u

typedef struct {
    bool in_use;
    wsg_conn_t conn;
    ip_addr_t addr;
    u16_t port;
    u32_t last_ms;
} udp_peer_t;

static struct udp_pcb *udp;
static udp_peer_t peers[GCL_UDP_MAX_PEERS];

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    (void)kind; /* UDP may lose any datagram; the peer retries */
    udp_peer_t *peer = ctx;
    struct pbuf *p = pbuf_alloc(PBUF_TRANSPORT, (u16_t)len, PBUF_RAM);
    if (p == NULL) {
        return;
    }
    memcpy(p->payload, line, len);
    (void)udp_sendto(udp, p, &peer->addr, peer->port);
    pbuf_free(p);
}

static const wsg_conn_io_t udp_io = {write_line};

static void forget(udp_peer_t *peer, wsg_close_reason_t reason)
{
    wsg_conn_close(&peer->conn, reason);
    memset(peer, 0, sizeof(*peer));
}

static udp_peer_t *find_or_add(const ip_addr_t *addr, u16_t port)
{
    udp_peer_t *free_slot = NULL;
    for (unsigned i = 0; i < GCL_UDP_MAX_PEERS; i++) {
        udp_peer_t *peer = &peers[i];
        if (!peer->in_use) {
            free_slot = free_slot != NULL ? free_slot : peer;
        } else if (peer->port == port && ip_addr_cmp(&peer->addr, addr)) {
            return peer;
        }
    }
    if (free_slot == NULL) {
        return NULL;
    }
    wsg_conn_open(&free_slot->conn, app_device(), &wsg_gcl_driver, WSG_TRANSPORT_DATAGRAM, &udp_io,
                  free_slot);
    free_slot->in_use = true;
    ip_addr_copy(free_slot->addr, *addr);
    free_slot->port = port;
    return free_slot;
}

static void on_recv(void *arg, struct udp_pcb *pcb, struct pbuf *p, const ip_addr_t *addr,
                    u16_t port)
{
    (void)arg;
    (void)pcb;
    udp_peer_t *peer = find_or_add(addr, port);
    if (peer == NULL) {
        hal_log(HAL_LOG_WARN, "udp: datagram dropped, all sessions in use");
        pbuf_free(p);
        return;
    }
    app_advance();
    for (struct pbuf *q = p; q != NULL; q = q->next) {
        wsg_conn_input(&peer->conn, q->payload, q->len);
    }
    wsg_conn_end_datagram(&peer->conn);
    app_note_input();
    pbuf_free(p);
    peer->last_ms = sys_now();
    if (wsg_conn_wants_close(&peer->conn)) {
        forget(peer, WSG_CLOSE_ANNOUNCED);
    }
}

bool gcl_udp_init(uint16_t port)
{
    udp = udp_new_ip_type(IPADDR_TYPE_V4);
    if (udp == NULL || udp_bind(udp, IP4_ADDR_ANY, port) != ERR_OK) {
        return false;
    }
    udp_recv(udp, on_recv, NULL);
    return true;
}

void gcl_udp_poll(void)
{
    u32_t now = sys_now();
    for (unsigned i = 0; i < GCL_UDP_MAX_PEERS; i++) {
        udp_peer_t *peer = &peers[i];
        if (peer->in_use && !wsg_conn_busy(&peer->conn) && now - peer->last_ms > PEER_IDLE_MS) {
            forget(peer, WSG_CLOSE_EXPIRED);
        }
    }
}
