/* GCL over TCP: one session per connection, each reply line its own send(). */
#ifndef HOST_TCP_SERVER_H
#define HOST_TCP_SERVER_H

#include <stdbool.h>

bool tcp_server_start(const char *addr, int port, int max_clients);
int tcp_server_port(void);
/* Closes connections that said BYE (once flushed) or failed. */
void tcp_server_reap(void);
/* Drops every connection as if its cable were pulled (no BYE). */
void tcp_server_close_all(void);
void tcp_server_stop(void);

#endif
