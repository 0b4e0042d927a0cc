/* SPDX-License-Identifier: BSD-3-Clause */
#include "gcl_tcp.h"

#include <string.h>

#include "app.h"
#include "board.h"
#include "hal_log.h"
#include "lwip/tcp.h"
#include "wsg/wsg_outq.h"

/* Messages wait here while lwIP's send buffer is full, by the core's queue
 * policy (wsg_outq.h): updates are dropped from half full on, and a client
 * whose reply does not fit loses its connection. */
#define TX_QUEUE 1024u

typedef struct {
    struct tcp_pcb *pcb; /* NULL: slot free */
    wsg_conn_t conn;
    bool has_conn;
    wsg_outq_t tx;
    uint8_t tx_ring[TX_QUEUE];
    bool closing; /* BYE answered: close once everything is sent */
    bool broken;  /* a reply did not fit: abort */
} tcp_conn_t;

static tcp_conn_t conns[GCL_TCP_MAX_CONNECTIONS];

/* Hands queued bytes to lwIP as far as its send buffer allows. */
static void flush(tcp_conn_t *c)
{
    while (!wsg_outq_empty(&c->tx)) {
        const char *bytes;
        size_t chunk = wsg_outq_front_chunk(&c->tx, &bytes);
        if (chunk > tcp_sndbuf(c->pcb)) {
            chunk = tcp_sndbuf(c->pcb);
        }
        if (chunk == 0u || tcp_write(c->pcb, bytes, (u16_t)chunk, TCP_WRITE_FLAG_COPY) != ERR_OK) {
            break;
        }
        wsg_outq_consume(&c->tx, chunk);
    }
    (void)tcp_output(c->pcb);
}

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    tcp_conn_t *c = ctx;
    if (c->pcb == NULL || c->broken) {
        return;
    }
    wsg_outq_result_t queued = wsg_outq_offer(&c->tx, line, len, kind);
    c->broken = queued == WSG_OUTQ_OVERFLOW;
    if (queued == WSG_OUTQ_QUEUED) {
        flush(c);
    }
}

static const wsg_conn_io_t tcp_io = {.write = write_line};

/* Detaches the connection from its pcb and session; frees the slot. */
static void release(tcp_conn_t *c, wsg_close_reason_t reason)
{
    if (c->has_conn) {
        wsg_conn_close(&c->conn, reason);
    }
    if (c->pcb != NULL) {
        tcp_arg(c->pcb, NULL);
        tcp_recv(c->pcb, NULL);
        tcp_sent(c->pcb, NULL);
        tcp_err(c->pcb, NULL);
        tcp_poll(c->pcb, NULL, 0);
    }
    memset(c, 0, sizeof(*c));
}

/* Closes gracefully (queued data and FIN still go out); aborts if lwIP has
 * no memory for that. Not for use inside this pcb's callbacks. */
static void close_conn(tcp_conn_t *c, wsg_close_reason_t reason)
{
    struct tcp_pcb *pcb = c->pcb;
    release(c, reason);
    if (tcp_close(pcb) != ERR_OK) {
        tcp_abort(pcb);
    }
}

static void on_err(void *arg, err_t err)
{
    (void)err;
    tcp_conn_t *c = arg;
    if (c != NULL) {
        c->pcb = NULL; /* lwIP has freed it already */
        release(c, c->closing ? WSG_CLOSE_ANNOUNCED : WSG_CLOSE_DROPPED);
        hal_log(HAL_LOG_INFO, "tcp: connection lost");
    }
}

static err_t on_recv(void *arg, struct tcp_pcb *pcb, struct pbuf *p, err_t err)
{
    tcp_conn_t *c = arg;
    if (p == NULL) {
        /* the client closed its side, after BYE, after the binary 0x07, or unannounced */
        bool announced = wsg_conn_close_announced(&c->conn);
        hal_log(HAL_LOG_INFO, c->closing  ? "tcp: closed after BYE"
                              : announced ? "tcp: closed after the disconnect announcement (0x07)"
                                          : "tcp: closed without BYE");
        release(c, announced ? WSG_CLOSE_ANNOUNCED : WSG_CLOSE_DROPPED);
        if (tcp_close(pcb) != ERR_OK) {
            tcp_abort(pcb);
            return ERR_ABRT;
        }
        return ERR_OK;
    }
    if (err == ERR_OK && !c->closing) {
        for (struct pbuf *q = p; q != NULL; q = q->next) {
            app_feed(&c->conn, q->payload, q->len, false);
        }
        c->closing = wsg_conn_wants_close(&c->conn);
    }
    tcp_recved(pcb, p->tot_len);
    pbuf_free(p);
    return ERR_OK;
}

static err_t on_sent(void *arg, struct tcp_pcb *pcb, u16_t len)
{
    (void)pcb;
    (void)len;
    flush(arg);
    return ERR_OK;
}

static err_t on_accept(void *arg, struct tcp_pcb *pcb, err_t err)
{
    (void)arg;
    if (err != ERR_OK || pcb == NULL) {
        return ERR_VAL;
    }
    tcp_conn_t *c = NULL;
    for (unsigned i = 0; i < GCL_TCP_MAX_CONNECTIONS && c == NULL; i++) {
        c = conns[i].pcb == NULL ? &conns[i] : NULL;
    }
    if (c == NULL) {
        hal_log(HAL_LOG_WARN, "tcp: connection refused, all sessions in use");
        tcp_abort(pcb);
        return ERR_ABRT;
    }
    /* the first byte chooses the protocol: 0xAA binary, else GCL */
    wsg_outq_init(&c->tx, c->tx_ring, sizeof(c->tx_ring));
    wsg_conn_open(&c->conn, app_device(), NULL, WSG_TRANSPORT_STREAM, &tcp_io, c);
    c->has_conn = true;
    c->pcb = pcb;
    tcp_arg(pcb, c);
    tcp_recv(pcb, on_recv);
    tcp_sent(pcb, on_sent);
    tcp_err(pcb, on_err);
    tcp_nagle_disable(pcb); /* a GCL line should leave at once */
    ip_set_option(pcb, SOF_KEEPALIVE);
    hal_log(HAL_LOG_INFO, "tcp: connection accepted");
    return ERR_OK;
}

bool gcl_tcp_init(uint16_t port)
{
    struct tcp_pcb *pcb = tcp_new_ip_type(IPADDR_TYPE_V4);
    if (pcb == NULL || tcp_bind(pcb, IP4_ADDR_ANY, port) != ERR_OK) {
        return false;
    }
    struct tcp_pcb *listener = tcp_listen_with_backlog(pcb, GCL_TCP_MAX_CONNECTIONS);
    if (listener == NULL) {
        tcp_close(pcb);
        return false;
    }
    tcp_accept(listener, on_accept);
    return true;
}

void gcl_tcp_poll(void)
{
    for (unsigned i = 0; i < GCL_TCP_MAX_CONNECTIONS; i++) {
        tcp_conn_t *c = &conns[i];
        if (c->pcb == NULL) {
            continue;
        }
        if (c->broken) {
            hal_log(HAL_LOG_WARN, "tcp: client does not read its replies, aborting");
            struct tcp_pcb *pcb = c->pcb;
            release(c, WSG_CLOSE_DROPPED);
            tcp_abort(pcb);
            continue;
        }
        flush(c);
        if (c->closing && wsg_outq_empty(&c->tx)) {
            close_conn(c, WSG_CLOSE_ANNOUNCED);
            board_log_stack_usage();
        }
    }
}
