/* GCL over TCP: one session per connection, each reply line its own send().
 * Connections have TCP keepalive; a half-closed one is answered and flushed
 * before it closes; idle_timeout_s (0: off) closes quiet connections. */
#ifndef HOST_TCP_SERVER_H
#define HOST_TCP_SERVER_H

#include <stdbool.h>

#include "wsg/wsg_conn.h"

bool tcp_server_start(const char *addr, int port, int max_clients, int idle_timeout_s);
int tcp_server_port(void);
/* Closes connections that said BYE (once flushed) or failed. */
void tcp_server_reap(void);
/* Drops every connection as if its cable were pulled (no BYE). */
void tcp_server_close_all(void);
/* Pulls the cable of the connection that carries this session: the session
 * ends without BYE and the socket is reset. False if none carries it. */
bool tcp_server_cut(const wsg_conn_t *conn);
void tcp_server_stop(void);

#endif
