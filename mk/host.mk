# SPDX-License-Identifier: BSD-3-Clause
# The Linux build of the virtual gripper: build/wsgsim, and the two
# libraries it links: libwsgfw.a (firmware/, the device core and its
# protocol drivers, the binary protocol's frame codec included) and
# libwsgsim.a (hal/sim/, the simulated hardware). Everything that links
# the core links both (CORE_LIBS), the simulation first: its finger nodes
# use the finger bus's wire format from libwsgfw.a.
# The host sees the public headers only (PUBLIC_INC); its capacities come
# from host/opts/wsgopts.h like every other Linux build of the libraries.
HOST_SRC := $(sort $(wildcard host/*.c host/sim/*.c))
HOST_PKGS := inih libcjson libsystemd
HOST_CFLAGS = $(CFLAGS_BASE) -D_GNU_SOURCE $(PUBLIC_INC) -Ihost $(shell pkg-config --cflags $(HOST_PKGS) 2>/dev/null)
HOST_LIBS = $(shell pkg-config --libs $(HOST_PKGS) 2>/dev/null) -lm

FW_LIB_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(FIRMWARE_SRC))
SIM_LIB_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(SIM_SRC))
CORE_OBJ := $(FW_LIB_OBJ) $(SIM_LIB_OBJ)
HOST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(HOST_SRC))
CORE_LIBS = $(BUILD)/libwsgsim.a $(BUILD)/libwsgfw.a

$(BUILD)/obj/firmware/%.o: firmware/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_BASE) $(FIRMWARE_INC) -ffreestanding -MMD -MP -c $< -o $@

$(BUILD)/obj/hal/%.o: hal/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_BASE) $(PUBLIC_INC) -MMD -MP -c $< -o $@

$(BUILD)/obj/host/%.o: host/%.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/libwsgfw.a: $(FW_LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/libwsgsim.a: $(SIM_LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/wsgsim: $(HOST_OBJ) $(CORE_LIBS)
	$(CC) $(LDFLAGS_BASE) -o $@ $(HOST_OBJ) $(CORE_LIBS) $(HOST_LIBS)

-include $(CORE_OBJ:.o=.d) $(HOST_OBJ:.o=.d)
