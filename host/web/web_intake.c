/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_intake.h"

#include <netinet/in.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "list.h"

/* The part of an address that is one client: an IPv4 address (as an
 * IPv4-mapped IPv6 one, so that both socket families compare alike) or an
 * IPv6 /64, what one host or site is usually given. */
typedef struct {
    unsigned char bytes[16];
} client_key_t;

struct web_intake_conn {
    bool in_use;
    bool arriving; /* its request is still arriving */
    bool url_nul;  /* its request's URL held %00 */
    int fd;
    client_key_t client;
    uint64_t since_ns; /* when it began to wait for this request */
    /* on the arriving list while arriving (oldest first: the deadline is
     * the same for all, so the head is due first), on the free list while
     * free */
    list_node_t link;
};

#define CONN(node) LIST_ITEM(node, web_intake_conn_t, link)

/* Every rule looks only at the connections whose request is arriving,
 * never at the whole pool: a request costs the same with 10 or 250 event
 * streams open. */
struct web_intake {
    web_intake_conn_t conns[WEB_INTAKE_CONNECTIONS_MAX];
    list_t free;
    list_t arriving;
    uint64_t deadline_ns;
};

web_intake_t *web_intake_create(void)
{
    web_intake_t *intake = calloc(1, sizeof(*intake));
    if (intake != NULL) {
        web_intake_reset(intake, 0);
    }
    return intake;
}

void web_intake_destroy(web_intake_t *intake)
{
    free(intake);
}

static client_key_t client_key(const struct sockaddr *addr)
{
    client_key_t key;
    memset(&key, 0, sizeof(key));
    if (addr != NULL && addr->sa_family == AF_INET) {
        struct sockaddr_in v4;
        memcpy(&v4, addr, sizeof(v4));
        key.bytes[10] = 0xffu;
        key.bytes[11] = 0xffu;
        memcpy(&key.bytes[12], &v4.sin_addr, 4);
    } else if (addr != NULL && addr->sa_family == AF_INET6) {
        struct sockaddr_in6 v6;
        memcpy(&v6, addr, sizeof(v6));
        bool mapped = IN6_IS_ADDR_V4MAPPED(&v6.sin6_addr);
        memcpy(key.bytes, &v6.sin6_addr, mapped ? 16u : 8u);
    }
    return key;
}

static void start_arriving(web_intake_t *intake, web_intake_conn_t *c, uint64_t now)
{
    c->arriving = true;
    c->since_ns = now;
    list_push_back(&intake->arriving, &c->link);
}

static void stop_arriving(web_intake_t *intake, web_intake_conn_t *c)
{
    if (!c->arriving) {
        return;
    }
    c->arriving = false;
    list_remove(&intake->arriving, &c->link);
}

void web_intake_reset(web_intake_t *intake, uint64_t deadline_ns)
{
    memset(intake, 0, sizeof(*intake));
    intake->deadline_ns = deadline_ns;
    for (unsigned i = 0; i < WEB_INTAKE_CONNECTIONS_MAX; i++) {
        list_push_back(&intake->free, &intake->conns[i].link);
    }
}

bool web_intake_admits(const web_intake_t *intake, const struct sockaddr *addr)
{
    client_key_t key = client_key(addr);
    unsigned arriving = 0;
    LIST_EACH (node, &intake->arriving) {
        const web_intake_conn_t *c = CONN(node);
        if (memcmp(&c->client, &key, sizeof(key)) == 0) {
            arriving++;
        }
    }
    return arriving < WEB_INTAKE_PER_ADDRESS;
}

web_intake_conn_t *web_intake_open(web_intake_t *intake, int fd, const struct sockaddr *addr,
                                   uint64_t now)
{
    list_node_t *node = list_pop_front(&intake->free);
    if (node == NULL) {
        return NULL;
    }
    web_intake_conn_t *c = CONN(node);
    *c = (web_intake_conn_t){.in_use = true, .fd = fd, .client = client_key(addr)};
    start_arriving(intake, c, now);
    return c;
}

void web_intake_arrived(web_intake_t *intake, web_intake_conn_t *conn)
{
    if (conn != NULL) {
        stop_arriving(intake, conn);
    }
}

void web_intake_waiting(web_intake_t *intake, web_intake_conn_t *conn, uint64_t now)
{
    if (conn != NULL) {
        stop_arriving(intake, conn); /* a connection arrives once, from now */
        start_arriving(intake, conn, now);
    }
}

void web_intake_note_nul(web_intake_conn_t *conn)
{
    if (conn != NULL) {
        conn->url_nul = true;
    }
}

bool web_intake_take_nul(web_intake_conn_t *conn)
{
    bool nul = conn != NULL && conn->url_nul;
    if (conn != NULL) {
        conn->url_nul = false;
    }
    return nul;
}

void web_intake_close(web_intake_t *intake, web_intake_conn_t *conn)
{
    if (conn != NULL && conn->in_use) {
        stop_arriving(intake, conn);
        conn->in_use = false;
        list_push_front(&intake->free, &conn->link);
    }
}

unsigned web_intake_cut_late(web_intake_t *intake, uint64_t now)
{
    unsigned cut = 0;
    while (!list_empty(&intake->arriving)) {
        web_intake_conn_t *c = CONN(intake->arriving.first);
        if (now < c->since_ns + intake->deadline_ns) {
            break;
        }
        /* MHD reads the end of the stream and closes it in its next run;
         * until then it is neither arriving nor cut again */
        shutdown(c->fd, SHUT_RDWR);
        stop_arriving(intake, c);
        cut++;
    }
    return cut;
}

uint64_t web_intake_next_due_ns(const web_intake_t *intake)
{
    const list_node_t *oldest = intake->arriving.first;
    return oldest != NULL ? CONN(oldest)->since_ns + intake->deadline_ns : 0u;
}
