/* GCL over UDP: one session per peer address; each reply line is its own
 * datagram, sent back to the peer that asked (AUTOSEND included). */
#ifndef HOST_UDP_SERVER_H
#define HOST_UDP_SERVER_H

#include <stdbool.h>

bool udp_server_start(const char *addr, int port);
int udp_server_port(void);
/* Forgets peers that said BYE or stayed silent too long. */
void udp_server_reap(void);
void udp_server_close_all(void);
void udp_server_stop(void);

#endif
