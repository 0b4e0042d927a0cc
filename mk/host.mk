# The Linux build of the virtual gripper: build/wsgsim.
# The session table's host size (128 TCP + 16 UDP) is the default in
# firmware/wsg_device.h, so everything linking libwsgcore.a agrees on it.
HOST_SRC := $(sort $(wildcard host/*.c))
HOST_PKGS := inih libcjson libsystemd
HOST_CFLAGS = $(CFLAGS_BASE) -D_GNU_SOURCE $(CORE_INC) -Ihost $(shell pkg-config --cflags $(HOST_PKGS) 2>/dev/null)
HOST_LIBS = $(shell pkg-config --libs $(HOST_PKGS) 2>/dev/null) -lm

CORE_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(FIRMWARE_SRC) $(SIM_SRC))
HOST_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(HOST_SRC))

$(BUILD)/obj/firmware/%.o: firmware/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_BASE) $(CORE_INC) -ffreestanding -MMD -MP -c $< -o $@

$(BUILD)/obj/hal/%.o: hal/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CFLAGS_BASE) $(CORE_INC) -MMD -MP -c $< -o $@

$(BUILD)/obj/host/%.o: host/%.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(HOST_CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/libwsgcore.a: $(CORE_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/wsgsim: $(HOST_OBJ) $(BUILD)/libwsgcore.a
	$(CC) $(LDFLAGS_BASE) -o $@ $(HOST_OBJ) $(BUILD)/libwsgcore.a $(HOST_LIBS)

-include $(CORE_OBJ:.o=.d) $(HOST_OBJ:.o=.d)
