/* SPDX-License-Identifier: BSD-3-Clause */
#include "lan9118.h"

#include "board.h"
#include "hal_clock.h"

/* Directly addressed registers (byte offsets) */
#define RX_DATA_FIFO 0x00u
#define TX_DATA_FIFO 0x20u
#define RX_STATUS_FIFO 0x40u
#define TX_STATUS_FIFO 0x48u
#define ID_REV 0x50u
#define IRQ_CFG 0x54u
#define INT_STS 0x58u
#define INT_EN 0x5Cu
#define BYTE_TEST 0x64u
#define FIFO_INT 0x68u
#define TX_CFG 0x70u
#define HW_CFG 0x74u
#define RX_FIFO_INF 0x7Cu
#define TX_FIFO_INF 0x80u
#define PMT_CTRL 0x84u
#define MAC_CSR_CMD 0xA4u
#define MAC_CSR_DATA 0xA8u

#define REG(off) REG32(LAN9118_BASE + (off))

#define BYTE_TEST_VALUE 0x87654321u
#define HW_CFG_SRST (1u << 0)
#define PMT_CTRL_READY (1u << 0)
#define TX_CFG_TX_ON (1u << 1)
#define IRQ_CFG_TYPE_PUSH_PULL (1u << 0)
#define IRQ_CFG_POL_HIGH (1u << 4)
#define IRQ_CFG_EN (1u << 8)
#define INT_RSFL (1u << 3) /* RX status FIFO level reached */
#define MAC_CSR_BUSY (1u << 31)
#define MAC_CSR_READ (1u << 30)

/* MAC control and status registers (indirect, through MAC_CSR_CMD) */
#define MAC_CR 1u
#define MAC_ADDRH 2u
#define MAC_ADDRL 3u
#define MAC_CR_RXEN (1u << 2)
#define MAC_CR_TXEN (1u << 3)
#define MAC_CR_FDPX (1u << 20)

/* RX status word */
#define RX_STS_LEN(s) (((s) >> 16) & 0x3FFFu)
#define RX_STS_ERROR (1u << 15)
/* TX command words */
#define TX_CMD_A_FIRST (1u << 13)
#define TX_CMD_A_LAST (1u << 12)

#define RESET_TIMEOUT_US 100000u
#define CRC_BYTES 4u

static size_t rx_pending_len; /* announced by lan9118_rx_next(), not yet read */

static bool wait_clear(uint32_t off, uint32_t mask)
{
    uint64_t start = hal_clock_now_us();
    while ((REG(off) & mask) != 0u) {
        if (hal_clock_now_us() - start > RESET_TIMEOUT_US) {
            return false;
        }
    }
    return true;
}

static uint32_t mac_read(uint32_t index)
{
    (void)wait_clear(MAC_CSR_CMD, MAC_CSR_BUSY);
    REG(MAC_CSR_CMD) = MAC_CSR_BUSY | MAC_CSR_READ | index;
    (void)wait_clear(MAC_CSR_CMD, MAC_CSR_BUSY);
    return REG(MAC_CSR_DATA);
}

static void mac_write(uint32_t index, uint32_t value)
{
    (void)wait_clear(MAC_CSR_CMD, MAC_CSR_BUSY);
    REG(MAC_CSR_DATA) = value;
    REG(MAC_CSR_CMD) = MAC_CSR_BUSY | index;
    (void)wait_clear(MAC_CSR_CMD, MAC_CSR_BUSY);
}

static bool soft_reset(void)
{
    if (REG(BYTE_TEST) != BYTE_TEST_VALUE) {
        return false;
    }
    REG(HW_CFG) = HW_CFG_SRST;
    if (!wait_clear(HW_CFG, HW_CFG_SRST)) {
        return false;
    }
    uint64_t start = hal_clock_now_us();
    while ((REG(PMT_CTRL) & PMT_CTRL_READY) == 0u) {
        if (hal_clock_now_us() - start > RESET_TIMEOUT_US) {
            return false;
        }
    }
    return true;
}

/* The address the EEPROM loaded, unless it is blank. */
static void read_mac(uint8_t mac[6])
{
    uint32_t lo = mac_read(MAC_ADDRL);
    uint32_t hi = mac_read(MAC_ADDRH);
    if ((lo == 0u && (hi & 0xFFFFu) == 0u) || (lo == 0xFFFFFFFFu && (hi & 0xFFFFu) == 0xFFFFu)) {
        return;
    }
    for (unsigned i = 0; i < 4; i++) {
        mac[i] = (uint8_t)(lo >> (8u * i));
    }
    mac[4] = (uint8_t)hi;
    mac[5] = (uint8_t)(hi >> 8);
}

static void write_mac(const uint8_t mac[6])
{
    mac_write(MAC_ADDRL, (uint32_t)mac[0] | (uint32_t)mac[1] << 8 | (uint32_t)mac[2] << 16 |
                             (uint32_t)mac[3] << 24);
    mac_write(MAC_ADDRH, (uint32_t)mac[4] | (uint32_t)mac[5] << 8);
}

bool lan9118_init(uint8_t mac[6])
{
    if (!soft_reset()) {
        return false;
    }
    read_mac(mac);
    write_mac(mac);
    /* The interrupt line idles low and rises on an enabled event; the
     * default (open drain, active low) would hold the NVIC input high. */
    REG(IRQ_CFG) = IRQ_CFG_EN | IRQ_CFG_POL_HIGH | IRQ_CFG_TYPE_PUSH_PULL;
    REG(FIFO_INT) = 0u; /* RSFL: as soon as one frame waits */
    REG(INT_STS) = 0xFFFFFFFFu;
    REG(INT_EN) = INT_RSFL;
    REG(TX_CFG) = TX_CFG_TX_ON;
    /* Exact address filter (no promiscuous mode), broadcasts accepted. */
    mac_write(MAC_CR, MAC_CR_TXEN | MAC_CR_RXEN | MAC_CR_FDPX);
    rx_pending_len = 0;
    return REG(ID_REV) != 0u;
}

void lan9118_irq_ack(void)
{
    REG(INT_STS) = REG(INT_STS);
}

static void rx_discard(size_t words)
{
    /* Read the words out rather than using the fast-forward command, whose
     * QEMU model has not always kept its FIFO accounting right. */
    while (words-- > 0u) {
        (void)REG(RX_DATA_FIFO);
    }
}

size_t lan9118_rx_next(void)
{
    while (((REG(RX_FIFO_INF) >> 16) & 0xFFu) != 0u) {
        uint32_t status = REG(RX_STATUS_FIFO);
        size_t len = RX_STS_LEN(status);
        bool bad = (status & RX_STS_ERROR) != 0u || len <= CRC_BYTES || len > LAN9118_FRAME_MAX;
        if (!bad) {
            rx_pending_len = len - CRC_BYTES;
            return rx_pending_len;
        }
        rx_discard((len + 3u) / 4u);
    }
    return 0;
}

void lan9118_rx_read(uint32_t *words)
{
    size_t count = (rx_pending_len + CRC_BYTES + 3u) / 4u;
    for (size_t i = 0; i < count; i++) {
        words[i] = REG(RX_DATA_FIFO);
    }
    rx_pending_len = 0;
}

/* Transmit statuses are not needed, but a full status FIFO stops the
 * transmitter on real hardware: discard them. */
static void tx_status_drain(void)
{
    while (((REG(TX_FIFO_INF) >> 16) & 0xFFu) != 0u) {
        (void)REG(TX_STATUS_FIFO);
    }
}

bool lan9118_tx(const uint32_t *words, size_t len)
{
    tx_status_drain();
    size_t count = (len + 3u) / 4u;
    uint32_t free_bytes = REG(TX_FIFO_INF) & 0xFFFFu;
    if (len == 0u || len > LAN9118_FRAME_MAX || free_bytes < count * 4u + 8u) {
        return false;
    }
    /* One buffer per frame: command A (first and last segment, no offset,
     * no end alignment), command B (frame length; the tag is unused). */
    REG(TX_DATA_FIFO) = TX_CMD_A_FIRST | TX_CMD_A_LAST | (uint32_t)len;
    REG(TX_DATA_FIFO) = (uint32_t)len;
    for (size_t i = 0; i < count; i++) {
        REG(TX_DATA_FIFO) = words[i];
    }
    return true;
}
