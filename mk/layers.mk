# SPDX-License-Identifier: BSD-3-Clause
# The shape of the sources, checked from the build (docs/architecture.md).
#   layers-check   no object of a lower layer references a symbol defined in
#                  a higher one, and no objects reference each other in a
#                  cycle: host/ in the order of HOST_DIRS (mk/host.mk, lowest
#                  first, main.o on top), firmware/ in FIRMWARE_LAYERS; and no
#                  modules include each other in a circle (mk/include_cycles.py)
#   sizes          the production files over 600 lines and functions over
#                  60 (firmware/, hal/, host/; mk/sizes.py)
#   sizes-check    the same, failing when there is any
# The firmware's folders, lowest first; bin/ and gcl/ are peers, which may
# not reference each other either.
FIRMWARE_LAYERS := text fingers core conn bin,gcl

.PHONY: layers-check sizes sizes-check
# Not in the SAN=1 pass, which runs the suites of C code (docs/testing.md):
# the sources and the references between the objects are the same whatever
# SAN says.
ifneq ($(SAN),1)
CHECK_TARGETS += layers-check sizes-check
endif

## fail when a lower layer references a higher one, or objects or includes go round in a circle
layers-check: $(HOST_OBJ) $(CORE_OBJ)
	@python3 mk/layers.py $(BUILD)/obj/host "$(HOST_DIRS)" $(HOST_OBJ) \
		--place $(BUILD)/obj/gen/web_assets.o=web
	@python3 mk/layers.py $(BUILD)/obj/firmware "$(FIRMWARE_LAYERS)" $(FW_LIB_OBJ)
	@python3 mk/include_cycles.py $(PUBLIC_INC) $(HOST_INC) $(wildcard host/*.[ch] host/*/*.[ch])
	@python3 mk/include_cycles.py $(FIRMWARE_INC) $(wildcard firmware/*/*.[ch] hal/*.h hal/sim/*.[ch])

## list production files over 600 lines and functions over 60
sizes:
	python3 mk/sizes.py

## fail when a production file is over 600 lines or a function over 60
sizes-check:
	@python3 mk/sizes.py --check
