# native.mk — the native (POSIX, SIL) board executables.
#
#   build/native/<board>       -O2, no sanitizers: what hil_sim runs (speed)
#   build/native-asan/<board>  ASan/UBSan: what tests/firmware/test_native_*.py run
#
# Each links one board (boards/<board>/*.c) with the shared firmware code
# (common/, drivers/) and the native HAL backend (hal/native/). Objects of the
# shared code are built once per flavour; board code and main.c per board.
# Board list and board sources come from boards.mk.

NATIVE_FLAVOURS := native native-asan
NATIVE_INC := -I$(FW)/hal -I$(FW)/hal/native -I$(FW)/common -I$(FW)/drivers -I$(FW)/boards
NATIVE_LIBS := -lm

# -O2 comes after NATIVE_CFLAGS' -O1 and wins; the release flavour drops -g to keep
# the executables small (the asan flavour keeps it for readable reports).
FLAVOUR_CFLAGS_native := $(NATIVE_CFLAGS) -O2
FLAVOUR_CFLAGS_native-asan := $(NATIVE_CFLAGS) $(SANITIZE)
FLAVOUR_LDFLAGS_native :=
FLAVOUR_LDFLAGS_native-asan := $(SANITIZE)

NATIVE_HAL_SRCS := $(filter-out $(FW)/hal/native/main.c,$(wildcard $(FW)/hal/native/*.c))
NATIVE_SHARED_SRCS := $(FW_SHARED_SRCS) $(NATIVE_HAL_SRCS)

# $(1) flavour: shared objects and the compile rule for everything under firmware/
define NATIVE_FLAVOUR_RULES
$(BUILD)/obj/fw-$(1)/%.o: $(FW)/%.c
	@mkdir -p $$(@D)
	$$(NATIVE_CC) $$(FLAVOUR_CFLAGS_$(1)) $$(NATIVE_INC) $$(BOARD_INC) -MMD -MP -c $$< -o $$@
NATIVE_SHARED_OBJS_$(1) := $$(patsubst $(FW)/%.c,$(BUILD)/obj/fw-$(1)/%.o,$$(NATIVE_SHARED_SRCS))
endef
$(foreach f,$(NATIVE_FLAVOURS),$(eval $(call NATIVE_FLAVOUR_RULES,$(f))))

# $(1) flavour, $(2) board
define NATIVE_BOARD_RULES
NATIVE_BOARD_OBJS_$(1)_$(2) := \
  $$(patsubst $(FW)/%.c,$(BUILD)/obj/fw-$(1)/%.o,$$(BOARD_SRCS_$(2))) \
  $(BUILD)/obj/fw-$(1)/main-$(2).o
$(BUILD)/obj/fw-$(1)/boards/$(2)/%.o: BOARD_INC := -I$(FW)/boards/$(2)
$(BUILD)/obj/fw-$(1)/main-$(2).o: $(FW)/hal/native/main.c
	@mkdir -p $$(@D)
	$$(NATIVE_CC) $$(FLAVOUR_CFLAGS_$(1)) $$(NATIVE_INC) -I$(FW)/boards/$(2) -MMD -MP -c $$< -o $$@
$(BUILD)/$(1)/$(2): $$(NATIVE_BOARD_OBJS_$(1)_$(2)) $$(NATIVE_SHARED_OBJS_$(1))
	@mkdir -p $$(@D)
	$$(NATIVE_CC) $$(FLAVOUR_LDFLAGS_$(1)) -o $$@ $$^ $$(NATIVE_LIBS)
-include $$(NATIVE_BOARD_OBJS_$(1)_$(2):.o=.d)
endef
$(foreach f,$(NATIVE_FLAVOURS),$(foreach b,$(FW_BOARDS),$(eval $(call NATIVE_BOARD_RULES,$(f),$(b)))))

-include $(NATIVE_SHARED_OBJS_native:.o=.d) $(NATIVE_SHARED_OBJS_native-asan:.o=.d)

NATIVE_BOARDS += $(addprefix $(BUILD)/native/,$(FW_BOARDS))
NATIVE_ASAN_BOARDS := $(addprefix $(BUILD)/native-asan/,$(FW_BOARDS))

.PHONY: native-asan
native-asan: $(NATIVE_ASAN_BOARDS)
