# boards.mk — which sources make each board, and the HAL/driver/board-wiring C tests.
#
# A board is everything in boards/<board>/ (board.c wiring + the algorithm modules)
# plus the board-independent wiring (boards/board_link.c; nav_ports.c for rover/base), the shared code in common/ and
# drivers/, and one HAL backend (native.mk, teensy32.mk).

FW_BOARDS := losa marker rover base
BOARDS_SHARED_SRCS := $(FW)/boards/board_link.c
# code every board links: protocol, ring buffer, quaternions, drivers, board_link
FW_SHARED_SRCS := $(wildcard $(FW)/common/*.c) $(wildcard $(FW)/drivers/*.c) $(BOARDS_SHARED_SRCS)
# a board: its wiring (board.c) + the algorithm modules algorithms.mk lists for it
# (rover and base share the VN200/SBP parsers and PWM capture)
BOARD_EXTRA_SRCS_rover := $(FW)/boards/nav_ports.c
BOARD_EXTRA_SRCS_base := $(FW)/boards/nav_ports.c
$(foreach b,$(FW_BOARDS),$(eval BOARD_SRCS_$(b) := $(FW)/boards/$(b)/board.c \
  $(BOARD_EXTRA_SRCS_$(b)) $(filter-out $(FW_SHARED_SRCS),$(ALGO_SRCS_$(b)))))

FW_TEST_CFLAGS := $(NATIVE_CFLAGS) $(SANITIZE)
FW_TEST_INC := -I$(FW)/hal -I$(FW)/hal/native -I$(FW)/common -I$(FW)/drivers -I$(FW)/boards \
               -I$(FW)/tests
# the scriptable HAL of the C tests (its SPI IMU is the native backend's MPU-9250 model)
FW_TEST_FAKE := $(FW)/tests/hal_fake.c $(FW)/hal/native/spi.c $(FW)/common/ringbuf.c

HAL_TESTS := ringbuf tsl1401 mpu9250
HAL_TEST_SRCS_ringbuf := $(FW)/common/ringbuf.c
HAL_TEST_SRCS_tsl1401 := $(FW)/drivers/tsl1401.c $(FW_TEST_FAKE)
HAL_TEST_SRCS_mpu9250 := $(FW)/drivers/mpu9250.c $(FW_TEST_FAKE)

define HAL_TEST_RULE
$(BUILD)/tests/test_hal_$(1): $(FW)/tests/test_hal_$(1).c $$(HAL_TEST_SRCS_$(1))
	@mkdir -p $$(@D)
	$$(NATIVE_CC) $$(FW_TEST_CFLAGS) $$(FW_TEST_INC) -MMD -MP -MF $$@.d -o $$@ $$^ -lm
-include $(BUILD)/tests/test_hal_$(1).d
endef
$(foreach t,$(HAL_TESTS),$(eval $(call HAL_TEST_RULE,$(t))))

# Board wiring tests: one per board that has firmware/tests/test_board_<board>.c.
BOARD_TESTS := $(foreach b,$(FW_BOARDS),$(if $(wildcard $(FW)/tests/test_board_$(b).c),$(b)))
FW_BOARD_TEST_COMMON := $(sort $(wildcard $(FW)/common/*.c) $(wildcard $(FW)/drivers/*.c) \
                        $(BOARDS_SHARED_SRCS) $(FW_TEST_FAKE))

define BOARD_TEST_RULE
$(BUILD)/tests/test_board_$(1): $(FW)/tests/test_board_$(1).c $$(BOARD_SRCS_$(1)) $$(FW_BOARD_TEST_COMMON)
	@mkdir -p $$(@D)
	$$(NATIVE_CC) $$(FW_TEST_CFLAGS) $$(FW_TEST_INC) -I$(FW)/boards/$(1) -MMD -MP -MF $$@.d \
	  -o $$@ $$^ -lm
-include $(BUILD)/tests/test_board_$(1).d
endef
$(foreach b,$(BOARD_TESTS),$(eval $(call BOARD_TEST_RULE,$(b))))

C_TESTS += $(addprefix $(BUILD)/tests/test_hal_,$(HAL_TESTS)) \
           $(addprefix $(BUILD)/tests/test_board_,$(BOARD_TESTS))

.PHONY: test-hal
test-hal: $(addprefix $(BUILD)/tests/test_hal_,$(HAL_TESTS)) \
          $(addprefix $(BUILD)/tests/test_board_,$(BOARD_TESTS))
	@set -e; for t in $^; do echo "run $${t#$(ROOT)/}"; $$t; done
