/* Socket helpers shared by the TCP and UDP servers. */
#ifndef HOST_NET_H
#define HOST_NET_H

#include <stdbool.h>
#include <sys/socket.h>

/* Creates, binds (and for SOCK_STREAM listens on) a non-blocking socket.
 * On failure prints one clear error line and returns -1. */
int net_listen(int type, const char *addr, int port);
/* The port a socket is bound to (useful with port 0). */
int net_local_port(int fd);
void net_format_peer(const struct sockaddr_storage *ss, char *out, size_t cap);

#endif
