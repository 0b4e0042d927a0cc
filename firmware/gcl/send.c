/* SPDX-License-Identifier: BSD-3-Clause */
/* Writing GCL lines: every reply, final reply and error of the driver and
 * its handlers goes out here. A leaf of the driver: it calls only the
 * connection and the text builder, so the handlers that send do not
 * depend on the driver that calls them. */
#include "gcl/gcl_internal.h"

static void notify_error_sent(gcl_conn_t *g, int command, wsg_status_t status)
{
    for (const wsg_gcl_observer_t *o = gcl_observers(g); o != NULL; o = o->next) {
        if (o->error_sent != NULL) {
            o->error_sent(o->ctx, conn_public(g->conn), command, status);
        }
    }
}

void wsg_gcl_send(gcl_conn_t *g, wsg_textbuf_t *tb, wsg_msg_kind_t kind)
{
    wsg_textbuf_put_char(tb, '\n');
    if (tb->overflow) {
        /* never hand out a cut line: report the overrun instead */
        wsg_textbuf_init(tb, tb->data, tb->cap);
        wsg_textbuf_put_str(tb, "ERR REPLY 27\n");
        notify_error_sent(g, -1, E_OVERRUN);
    }
    wsg_gcl_send_line(g, tb->data, tb->len, kind);
}

/* "ACK HOME", "FIN MOVE" */
void wsg_gcl_send_word(gcl_conn_t *g, const char *word, const char *name)
{
    char storage[64];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, word);
    wsg_textbuf_put_char(&tb, ' ');
    wsg_textbuf_put_str(&tb, name);
    wsg_gcl_send(g, &tb, WSG_MSG_REPLY);
}

void wsg_gcl_send_error(gcl_conn_t *g, const char *name, int command, wsg_status_t status)
{
    char storage[128];
    wsg_textbuf_t tb;
    wsg_textbuf_init(&tb, storage, sizeof(storage));
    wsg_textbuf_put_str(&tb, "ERR ");
    wsg_textbuf_put_str(&tb, name[0] != '\0' ? name : "?");
    wsg_textbuf_put_char(&tb, ' ');
    wsg_textbuf_put_uint(&tb, (uint32_t)status);
    if (g->verbose) {
        wsg_textbuf_put_char(&tb, ' ');
        wsg_textbuf_put_str(&tb, wsg_status_description(status));
    }
    notify_error_sent(g, command, status);
    wsg_gcl_send(g, &tb, WSG_MSG_REPLY);
}
