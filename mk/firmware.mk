# SPDX-License-Identifier: BSD-3-Clause
# The same core on a microcontroller: Cortex-M3 images for QEMU's mps2-an385.
#   make firmware        build/firmware/wsgsim-{serial,lwip}.{elf,bin}
#   make firmware-size   flash/RAM of both images against their budgets
#   make run-qemu        boot an image (FW_IMAGE=serial|lwip) and say how to connect
#   firmware-check       (part of make check) budgets, core symbol check, and the
#                        GCL and binary conversations against both images
#                        booted in QEMU (UART, TCP, UDP)
# See docs/firmware.md.

FW_BOARD := hal/boards/mps2-an385
FW_OUT := build/firmware
FW_LWIP_DIR := build/lwip
FW_LWIP_STAMP := $(FW_LWIP_DIR)/.fetched
FW_IMAGE ?= serial

FW_DEBS := gcc-arm-none-eabi binutils-arm-none-eabi libnewlib-arm-none-eabi
FW_QEMU_DEBS := qemu-system-arm python3
FW_LWIP_DEBS := dpkg-dev

FW_CROSS := arm-none-eabi-
FW_CC := $(FW_CROSS)gcc
FW_OBJCOPY := $(FW_CROSS)objcopy
FW_NM := $(FW_CROSS)nm
FW_SIZE := $(FW_CROSS)size

# Budgets (bytes): flash = .text + .data, RAM = .data + .bss + main stack.
FW_SERIAL_FLASH_MAX := 65536
FW_SERIAL_RAM_MAX := 16384
FW_LWIP_FLASH_MAX := 163840
FW_LWIP_RAM_MAX := 65536

# Connections: the serial image has one line; the lwIP image serves UART0
# plus up to 4 TCP connections, 4 GCL and 2 binary UDP peers (static storage
# in the board's ports). Capacities and options: $(FW_BOARD)/wsgopts.h (lwIP-style).
FW_SERIAL_STACK := 4096
FW_LWIP_STACK := 6144

FW_ARCH := -mcpu=cortex-m3 -mthumb -mfloat-abi=soft
FW_CFLAGS_COMMON := $(CSTD) $(FW_ARCH) -Os -g -ffunction-sections -fdata-sections -fno-common \
	-MMD -MP
FW_CFLAGS := $(FW_CFLAGS_COMMON) $(WARN) -I$(FW_BOARD) -Iinclude -Ihal -Ifirmware
FW_LWIP_INC := -I$(FW_BOARD)/lwip -I$(FW_LWIP_DIR)/src/include
# lwIP is third-party code: built with -Werror too, under the warnings it
# was written for (it predates -Wshadow/-Wmissing-prototypes hygiene).
FW_LWIP_CFLAGS := $(FW_CFLAGS_COMMON) -Wall -Wextra -Werror $(FW_LWIP_INC) -I$(FW_BOARD)
FW_LDFLAGS := $(FW_ARCH) -nostartfiles --specs=nano.specs -T $(FW_BOARD)/mps2-an385.ld \
	-Wl,--gc-sections -Wl,--fatal-warnings
FW_LIBS := -lm -lc -lgcc

FW_CORE_SRC := $(FIRMWARE_SRC) $(SIM_SRC)
FW_BOARD_COMMON := startup.c clock.c cmsdk_uart.c log.c no_heap.c app.c serial_port.c
FW_SERIAL_SRC := $(FW_CORE_SRC) $(addprefix $(FW_BOARD)/,$(FW_BOARD_COMMON) main_serial.c)
FW_LWIP_BOARD_SRC := $(FW_CORE_SRC) $(addprefix $(FW_BOARD)/,$(FW_BOARD_COMMON) main_lwip.c \
	lan9118.c lan9118_netif.c gcl_tcp.c lwip_udp.c lwip/sys_arch.c web_status.c)
# lwIP 2.1: IPv4 core, raw API, Ethernet/ARP, the httpd app (the status page);
# no sockets, no IPv6.
FW_LWIP_LIB_SRC := core/init.c core/def.c core/inet_chksum.c core/ip.c core/mem.c core/memp.c \
	core/netif.c core/pbuf.c core/tcp.c core/tcp_in.c core/tcp_out.c core/timeouts.c \
	core/udp.c core/ipv4/etharp.c core/ipv4/icmp.c core/ipv4/ip4.c core/ipv4/ip4_addr.c \
	core/ipv4/ip4_frag.c netif/ethernet.c apps/http/httpd.c apps/http/fs.c

FW_SERIAL_OBJ := $(patsubst %.c,$(FW_OUT)/obj/serial/%.o,$(FW_SERIAL_SRC))
FW_LWIP_OBJ := $(patsubst %.c,$(FW_OUT)/obj/lwip/%.o,$(FW_LWIP_BOARD_SRC)) \
	$(patsubst %.c,$(FW_OUT)/obj/lwip/lwip-lib/%.o,$(FW_LWIP_LIB_SRC))
FW_CORE_OBJ := $(patsubst %.c,$(FW_OUT)/obj/serial/%.o,$(FW_CORE_SRC))

FW_IMAGES := $(FW_OUT)/wsgsim-serial.elf $(FW_OUT)/wsgsim-lwip.elf
FW_BINS := $(FW_IMAGES:.elf=.bin)

.PHONY: firmware firmware-size firmware-check run-qemu fw-deps fw-qemu-deps
# Not in the SAN=1 pass, which runs the suites of C code (docs/testing.md):
# the images are cross-compiled the same either way.
ifneq ($(SAN),1)
CHECK_TARGETS += firmware-check
endif

## build the Cortex-M3 images build/firmware/wsgsim-{serial,lwip}.{elf,bin}
firmware: $(FW_IMAGES) $(FW_BINS) $(FW_OUT)/core-symbols.ok

## install the ARM cross toolchain
fw-deps:
	@mk/deps.sh $(FW_DEBS)

## install QEMU for the ARM images
fw-qemu-deps:
	@mk/deps.sh $(FW_QEMU_DEBS)

$(FW_LWIP_STAMP):
	@mk/deps.sh $(FW_LWIP_DEBS)
	$(FW_BOARD)/fetch-lwip.sh $(FW_LWIP_DIR)

$(FW_OUT)/obj/serial/%.o: %.c | fw-deps
	@mkdir -p $(dir $@)
	$(FW_CC) $(FW_CFLAGS) -c $< -o $@

$(FW_OUT)/obj/lwip/%.o: %.c | fw-deps $(FW_LWIP_STAMP)
	@mkdir -p $(dir $@)
	$(FW_CC) $(FW_CFLAGS) $(FW_LWIP_INC) -c $< -o $@

$(FW_OUT)/obj/lwip/lwip-lib/%.o: $(FW_LWIP_STAMP) | fw-deps
	@mkdir -p $(dir $@)
	$(FW_CC) $(FW_LWIP_CFLAGS) -c $(FW_LWIP_DIR)/src/$*.c -o $@

# Links, then enforces the budgets: an image over budget is not kept.
define fw_link
	$(FW_CC) $(FW_LDFLAGS) -Wl,--defsym=STACK_SIZE=$(4) -Wl,-Map=$(@:.elf=.map) \
		-o $@ $(2) $(FW_LIBS)
	@SIZE=$(FW_SIZE) NM=$(FW_NM) $(FW_BOARD)/size-check.sh $@ $(3) $(5) || { rm -f $@; exit 1; }
endef

$(FW_OUT)/wsgsim-serial.elf: $(FW_SERIAL_OBJ) $(FW_BOARD)/mps2-an385.ld $(FW_BOARD)/size-check.sh
	$(call fw_link,serial,$(FW_SERIAL_OBJ),$(FW_SERIAL_FLASH_MAX),$(FW_SERIAL_STACK),$(FW_SERIAL_RAM_MAX))

$(FW_OUT)/wsgsim-lwip.elf: $(FW_LWIP_OBJ) $(FW_BOARD)/mps2-an385.ld $(FW_BOARD)/size-check.sh
	$(call fw_link,lwip,$(FW_LWIP_OBJ),$(FW_LWIP_FLASH_MAX),$(FW_LWIP_STACK),$(FW_LWIP_RAM_MAX))

$(FW_OUT)/%.bin: $(FW_OUT)/%.elf
	$(FW_OBJCOPY) -O binary $< $@

$(FW_OUT)/core-symbols.ok: $(FW_CORE_OBJ) $(FW_BOARD)/check-core-symbols.sh
	@NM=$(FW_NM) $(FW_BOARD)/check-core-symbols.sh $(FW_CORE_OBJ)
	@touch $@

## the images' flash and RAM against their budgets
firmware-size: $(FW_IMAGES)
	@SIZE=$(FW_SIZE) NM=$(FW_NM) $(FW_BOARD)/size-check.sh $(FW_OUT)/wsgsim-serial.elf \
		$(FW_SERIAL_FLASH_MAX) $(FW_SERIAL_RAM_MAX)
	@SIZE=$(FW_SIZE) NM=$(FW_NM) $(FW_BOARD)/size-check.sh $(FW_OUT)/wsgsim-lwip.elf \
		$(FW_LWIP_FLASH_MAX) $(FW_LWIP_RAM_MAX)

## budgets, core symbols, and GCL and binary conversations with both images in QEMU
firmware-check: firmware firmware-size | fw-qemu-deps
	tests/qemu/boot.sh --test serial $(FW_OUT)/wsgsim-serial.elf
	tests/qemu/boot.sh --test lwip $(FW_OUT)/wsgsim-lwip.elf

## boot an image in QEMU (FW_IMAGE=serial|lwip) and say how to connect
run-qemu: $(FW_OUT)/wsgsim-$(FW_IMAGE).elf | fw-qemu-deps
	tests/qemu/boot.sh $(FW_IMAGE) $<

-include $(wildcard $(FW_SERIAL_OBJ:.o=.d) $(FW_LWIP_OBJ:.o=.d))
