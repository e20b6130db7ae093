# teensy32.mk — Teensy 3.2 (MK20DX256, Cortex-M4 without FPU) images, bare metal.
#
#   build/teensy32/<board>.elf  .hex  .map   for every board in FW_BOARDS
#
# The HAL backend is compiled per board (PINS_<NAME> selects the role -> pin map
# in hal/teensy32/board_pins.h); so is everything else, with the same flags.
# `make -C firmware teensy32` ends by printing flash / RAM use per board.

TEENSY_LD := $(FW)/hal/teensy32/mk20dx256.ld
TEENSY_INC := -I$(FW)/hal -I$(FW)/hal/teensy32 -I$(FW)/common -I$(FW)/drivers -I$(FW)/boards
TEENSY_HAL_SRCS := $(wildcard $(FW)/hal/teensy32/*.c)
TEENSY_LDFLAGS := -nostartfiles -Wl,--gc-sections -Wl,-T,$(TEENSY_LD) --specs=nano.specs
# no nosys.specs on purpose: a call into malloc/printf/syscalls fails the link (no heap)
TEENSY_LIBS := -lm -lc -lgcc
ARM_READELF := $(ARM_PREFIX)readelf

# $(1) board
define TEENSY_BOARD_RULES
TEENSY_SRCS_$(1) := $$(TEENSY_HAL_SRCS) $$(BOARD_SRCS_$(1)) $$(FW_SHARED_SRCS)
TEENSY_OBJS_$(1) := $$(patsubst $(FW)/%.c,$(BUILD)/obj/fw-teensy32/$(1)/%.o,$$(TEENSY_SRCS_$(1)))
$(BUILD)/obj/fw-teensy32/$(1)/%.o: $(FW)/%.c
	@mkdir -p $$(@D)
	@echo "  CC  teensy32/$(1)  $$(<:$(FW)/%=%)"
	@$$(ARM_CC) $$(ARM_CFLAGS) -DPINS_$(shell echo $(1) | tr a-z A-Z) $$(TEENSY_INC) \
	  -I$(FW)/boards/$(1) -MMD -MP -c $$< -o $$@
$(BUILD)/teensy32/$(1).elf: $$(TEENSY_OBJS_$(1)) $(TEENSY_LD)
	@mkdir -p $$(@D)
	@echo "  LD  $$(@:$(BUILD)/%=build/%)"
	@$$(ARM_CC) $$(ARM_CFLAGS) $$(TEENSY_LDFLAGS) -Wl,-Map,$(BUILD)/teensy32/$(1).map \
	  -o $$@ $$(TEENSY_OBJS_$(1)) $$(TEENSY_LIBS)
$(BUILD)/teensy32/$(1).hex: $(BUILD)/teensy32/$(1).elf
	@$$(ARM_OBJCOPY) -O ihex -R .bss -R .noinit $$< $$@
-include $$(TEENSY_OBJS_$(1):.o=.d)
endef
$(foreach b,$(FW_BOARDS),$(eval $(call TEENSY_BOARD_RULES,$(b))))

TEENSY_ELFS := $(addprefix $(BUILD)/teensy32/,$(addsuffix .elf,$(FW_BOARDS)))
TEENSY_IMAGES += $(addprefix $(BUILD)/teensy32/,$(addsuffix .hex,$(FW_BOARDS)))

# flash = .text + .ARM.exidx + .data (its load image); RAM = .data + .bss + .noinit,
# with 8 KiB of stack reserved on top (the linker script enforces it)
.PHONY: teensy32-sizes
teensy32: teensy32-sizes
teensy32-sizes: $(TEENSY_IMAGES)
	@for elf in $(TEENSY_ELFS); do \
	  $(ARM_SIZE) -A $$elf | awk -v name=$$(basename $$elf .elf) ' \
	    $$1 == ".text" || $$1 == ".ARM.exidx" { flash += $$2 } \
	    $$1 == ".data" { flash += $$2; ram += $$2 } \
	    $$1 == ".bss" || $$1 == ".noinit" { ram += $$2 } \
	    END { printf "teensy32 %-7s flash %7d B (%5.1f %% of 256 KiB)   RAM %6d B (%5.1f %% of 64 KiB, + 8 KiB stack)\n", \
	          name, flash, 100 * flash / 262144, ram, 100 * ram / 65536 }'; \
	done
