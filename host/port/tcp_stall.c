/* SPDX-License-Identifier: BSD-3-Clause */
/* The stalled-slot rule of the TCP servers (tcp_server.c): with every slot
 * taken, a connection stuck inside a command gives its slot to a newcomer. */
#include "hal_clock.h"
#include "tcp_client.h"

/* Stuck: no whole command for the grace, and either inside one now (a
 * line without its end, a frame cut short) or none completed at all. */
static bool stalled(const tcp_client_t *c, uint64_t now, uint64_t grace_us)
{
    bool unfinished = c->messages_in == 0 || wsg_conn_partial_input(&c->conn);
    return unfinished && now - c->completed_us >= grace_us;
}

/* The stalled connection that completed a command longest ago; its slot
 * goes to a waiting client. */
tcp_client_t *tcp_stalled_connection(const tcp_server_t *s, uint64_t grace_us)
{
    uint64_t now = hal_clock_now_us();
    tcp_client_t *found = NULL;
    LIST_EACH (node, &s->set->clients) {
        tcp_client_t *c = CLIENT(node);
        if (c->server == s && stalled(c, now, grace_us) &&
            (found == NULL || c->completed_us < found->completed_us)) {
            found = c;
        }
    }
    return found;
}
