/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_intake.h"

#include <netinet/in.h>
#include <string.h>
#include <sys/socket.h>

/* The part of an address that is one client: an IPv4 address (as an
 * IPv4-mapped IPv6 one, so that both socket families compare alike) or an
 * IPv6 /64, what one host or site is usually given. */
typedef struct {
    unsigned char bytes[16];
} client_key_t;

struct web_intake_conn {
    bool in_use;
    bool arriving; /* its request is still arriving */
    int fd;
    client_key_t client;
    uint64_t since_ns; /* when it began to wait for this request */
};

static struct {
    web_intake_conn_t conns[WEB_INTAKE_CONNECTIONS_MAX];
    uint64_t deadline_ns;
    uint64_t next_due_ns; /* the oldest arriving connection's deadline, 0: none */
} intake;

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

static void update_next_due(void)
{
    intake.next_due_ns = 0;
    for (unsigned i = 0; i < WEB_INTAKE_CONNECTIONS_MAX; i++) {
        const web_intake_conn_t *c = &intake.conns[i];
        uint64_t due = c->since_ns + intake.deadline_ns;
        if (c->in_use && c->arriving && (intake.next_due_ns == 0 || due < intake.next_due_ns)) {
            intake.next_due_ns = due;
        }
    }
}

void web_intake_reset(uint64_t deadline_ns)
{
    memset(&intake, 0, sizeof(intake));
    intake.deadline_ns = deadline_ns;
}

bool web_intake_admits(const struct sockaddr *addr)
{
    client_key_t key = client_key(addr);
    unsigned arriving = 0;
    for (unsigned i = 0; i < WEB_INTAKE_CONNECTIONS_MAX; i++) {
        const web_intake_conn_t *c = &intake.conns[i];
        if (c->in_use && c->arriving && memcmp(&c->client, &key, sizeof(key)) == 0) {
            arriving++;
        }
    }
    return arriving < WEB_INTAKE_PER_ADDRESS;
}

web_intake_conn_t *web_intake_open(int fd, const struct sockaddr *addr, uint64_t now)
{
    for (unsigned i = 0; i < WEB_INTAKE_CONNECTIONS_MAX; i++) {
        web_intake_conn_t *c = &intake.conns[i];
        if (!c->in_use) {
            *c = (web_intake_conn_t){
                .in_use = true, .arriving = true, .fd = fd, .client = client_key(addr)};
            web_intake_waiting(c, now);
            return c;
        }
    }
    return NULL;
}

void web_intake_arrived(web_intake_conn_t *conn)
{
    if (conn != NULL && conn->arriving) {
        conn->arriving = false;
        update_next_due();
    }
}

void web_intake_waiting(web_intake_conn_t *conn, uint64_t now)
{
    if (conn != NULL) {
        conn->arriving = true;
        conn->since_ns = now;
        update_next_due();
    }
}

void web_intake_close(web_intake_conn_t *conn)
{
    if (conn != NULL) {
        conn->in_use = false;
        update_next_due();
    }
}

unsigned web_intake_cut_late(uint64_t now)
{
    unsigned cut = 0;
    for (unsigned i = 0; i < WEB_INTAKE_CONNECTIONS_MAX; i++) {
        web_intake_conn_t *c = &intake.conns[i];
        if (c->in_use && c->arriving && now >= c->since_ns + intake.deadline_ns) {
            /* MHD reads the end of the stream and closes it in its next run;
             * until then it is neither arriving nor cut again */
            shutdown(c->fd, SHUT_RDWR);
            c->arriving = false;
            cut++;
        }
    }
    if (cut > 0) {
        update_next_due();
    }
    return cut;
}

uint64_t web_intake_next_due_ns(void)
{
    return intake.next_due_ns;
}
