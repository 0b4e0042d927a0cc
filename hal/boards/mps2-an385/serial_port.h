/* SPDX-License-Identifier: BSD-3-Clause */
/* GCL over UART0: one stream session that is always open. A serial line
 * has no connection to lose, so BYE ends the session and a fresh one (with
 * default settings) takes its place at once. */
#ifndef SERIAL_PORT_H
#define SERIAL_PORT_H

void serial_port_init(void);

/* Feeds what UART0 received to the session. */
void serial_port_poll(void);

#endif
