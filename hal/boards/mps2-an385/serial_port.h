/* SPDX-License-Identifier: BSD-3-Clause */
/* GCL or the binary protocol over UART0: one session that is always open
 * (WSG_TRANSPORT_SERIAL); its first byte chooses the protocol (0xAA binary,
 * else GCL), as on TCP. A serial line has no connection to lose, so GCL's
 * BYE ends the session and a fresh one (default settings, protocol chosen
 * again) takes its place at once; the binary 0x07 answers E_NOT_AVAILABLE,
 * so a binary session lasts until the board resets. */
#ifndef SERIAL_PORT_H
#define SERIAL_PORT_H

void serial_port_init(void);

/* Feeds what UART0 received to the session. */
void serial_port_poll(void);

#endif
