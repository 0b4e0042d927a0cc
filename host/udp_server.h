/* GCL over UDP: one session per peer address; each reply line is its own
 * datagram, sent back to the peer that asked (AUTOSEND included). A peer
 * silent for peer_timeout_s is forgotten (its AUTOSEND ends), what it gets
 * is bounded by what it sent, and the server's own addresses are ignored. */
#ifndef HOST_UDP_SERVER_H
#define HOST_UDP_SERVER_H

#include <stdbool.h>

#include "wsg/wsg_conn.h"

bool udp_server_start(const char *addr, int port, int peer_timeout_s);
int udp_server_port(void);
/* Forgets peers that said BYE or stayed silent too long (unless running a
 * motion). */
void udp_server_reap(void);
void udp_server_close_all(void);
/* Forgets the peer that owns this session, as if it vanished without BYE.
 * False if no peer owns it. */
bool udp_server_cut(const wsg_conn_t *conn);
void udp_server_stop(void);

#endif
