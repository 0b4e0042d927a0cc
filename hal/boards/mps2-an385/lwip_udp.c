/* SPDX-License-Identifier: BSD-3-Clause */
#include "lwip_udp.h"

#include <string.h>

#include "app.h"
#include "hal_log.h"
#include "lwip/udp.h"

/* A peer's identity as the table compares it: its address, then its port. */
typedef struct {
    ip_addr_t ip;
    u16_t port;
} peer_addr_t;

_Static_assert(sizeof(peer_addr_t) <= WSG_PEER_ADDR_BYTES, "WSG_PEER_ADDR_BYTES too small");

static wsg_peer_addr_t key_of(const ip_addr_t *ip, u16_t port)
{
    peer_addr_t a;
    memset(&a, 0, sizeof(a)); /* padding compares too */
    ip_addr_copy(a.ip, *ip);
    a.port = port;
    wsg_peer_addr_t key = {.len = (uint8_t)sizeof(a)};
    memcpy(key.bytes, &a, sizeof(a));
    return key;
}

static void write_message(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    wsg_peer_t *peer = ctx;
    lwip_udp_server_t *s = peer->port_ctx;
    if (!wsg_peers_may_send(&s->peers, peer, len, kind)) {
        return; /* lost, as a datagram may be */
    }
    peer_addr_t to;
    memcpy(&to, peer->addr.bytes, sizeof(to));
    struct pbuf *p = pbuf_alloc(PBUF_TRANSPORT, (u16_t)len, PBUF_RAM);
    if (p == NULL) {
        return;
    }
    memcpy(p->payload, bytes, len);
    (void)udp_sendto(s->pcb, p, &to.ip, s->reply_port != 0 ? s->reply_port : to.port);
    pbuf_free(p);
}

static const wsg_conn_io_t udp_io = {.write = write_message};

static wsg_peer_t *new_peer(lwip_udp_server_t *s, const wsg_peer_addr_t *key)
{
    wsg_peer_t *peer = wsg_peers_make_room(&s->peers) ? wsg_peers_take_free(&s->peers) : NULL;
    if (peer == NULL) {
        return NULL;
    }
    wsg_peers_add(&s->peers, peer, key);
    peer->port_ctx = s;
    wsg_conn_open(&peer->conn, app_device(), s->driver, WSG_TRANSPORT_DATAGRAM, &udp_io, peer);
    return peer;
}

static void on_recv(void *arg, struct udp_pcb *pcb, struct pbuf *p, const ip_addr_t *addr,
                    u16_t port)
{
    (void)pcb;
    lwip_udp_server_t *s = arg;
    wsg_peer_addr_t key = key_of(addr, port);
    wsg_peer_t *peer = wsg_peers_session_for(&s->peers, &key); /* after BYE: a fresh one */
    if (peer == NULL && (peer = new_peer(s, &key)) == NULL) {
        hal_log(HAL_LOG_WARN, "udp: datagram dropped, every peer is live");
        pbuf_free(p);
        return;
    }
    wsg_peers_heard(&s->peers, peer, p->tot_len);
    for (struct pbuf *q = p; q != NULL; q = q->next) {
        app_feed(&peer->conn, q->payload, q->len, q->next == NULL);
    }
    pbuf_free(p);
}

bool lwip_udp_start(lwip_udp_server_t *s, const wsg_proto_driver_t *driver, uint16_t port,
                    uint16_t reply_port, wsg_peer_t *pool, unsigned count)
{
    wsg_peer_rules_t rules = WSG_PEER_RULES_DEFAULT(count, LWIP_UDP_PEER_TIMEOUT_S);
    wsg_peers_init(&s->peers, &rules, NULL, NULL, pool, count);
    s->driver = driver;
    s->reply_port = reply_port;
    s->pcb = udp_new_ip_type(IPADDR_TYPE_V4);
    if (s->pcb == NULL || udp_bind(s->pcb, IP4_ADDR_ANY, port) != ERR_OK) {
        return false;
    }
    udp_recv(s->pcb, on_recv, s);
    return true;
}

void lwip_udp_poll(lwip_udp_server_t *s)
{
    wsg_peers_reap(&s->peers);
}
