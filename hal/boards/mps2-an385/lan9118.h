/* SPDX-License-Identifier: BSD-3-Clause */
/* SMSC LAN9118 Ethernet controller (32-bit bus, PIO FIFOs), as wired on the
 * MPS2 and modelled by QEMU: just enough to send and receive frames. */
#ifndef LAN9118_H
#define LAN9118_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define LAN9118_FRAME_MAX 1536u /* the largest frame the FIFOs take, CRC included */

/* Resets the controller, reads its MAC address (from its EEPROM; mac is left
 * untouched if there is none), and enables the MAC for transmit and receive
 * with the receive interrupt. False if no LAN9118 answers. */
bool lan9118_init(uint8_t mac[6]);

/* Length of the next received frame without its CRC, or 0 if none waits.
 * Frames with errors are dropped here. */
size_t lan9118_rx_next(void);

/* Reads the frame that lan9118_rx_next() announced into words, which must
 * hold LAN9118_FRAME_MAX bytes (the CRC is read out too). */
void lan9118_rx_read(uint32_t *words);

/* Queues one frame for transmission. False if the FIFO has no room. */
bool lan9118_tx(const uint32_t *words, size_t len);

/* The interrupt handler's part: acknowledges what the controller raised. */
void lan9118_irq_ack(void);

#endif
