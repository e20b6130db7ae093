# algorithms.mk — the boards' pure algorithm modules (brief F2): LOSA peaks/slots/
# exposure, marker attitude + LED logic, VN200/SBP parsers, rotor speed, PWM/SBUS.
#
#   ALGO_SRCS_<board>            the algorithm sources each board links (boards.mk/
#                                board wiring: rover and base share parsers/capture)
#   build/native/algo_tests/*    C unit tests (ASan/UBSan), in C_TESTS
#   build/native/libawboards.so  every module in one shared library for the Python
#                                cross-checks (tests/firmware_algos, ctypes)
#   build/native/algo_bench/*    callgrind drivers (firmware/bench/bench.py)
#   build/teensy32/algos/*.o     the modules for the M4 (-Os, soft float): code size
# Include paths as the board builds use them: -I common -I boards.

ALGO_INC := -I$(FW)/common -I$(FW)/boards
ALGO_SRCS_losa := $(addprefix $(FW)/boards/losa/,peak.c slots.c exposure.c frame.c)
ALGO_SRCS_marker := $(addprefix $(FW)/boards/marker/,leds.c attitude.c marker_logic.c young81000.c) $(FW)/common/quat.c
ALGO_SRCS_parsers := $(addprefix $(FW)/boards/rover/,crc16_xmodem.c vn200.c sbp.c)
ALGO_SRCS_rover := $(ALGO_SRCS_parsers) $(FW)/boards/rover/rotor_speed.c $(FW)/boards/base/pwm_capture.c
ALGO_SRCS_base := $(ALGO_SRCS_parsers) $(addprefix $(FW)/boards/base/,pwm_capture.c sbus.c)
ALGO_SRCS := $(sort $(ALGO_SRCS_losa) $(ALGO_SRCS_marker) $(ALGO_SRCS_rover) $(ALGO_SRCS_base))
ALGO_HDRS := $(ALGO_SRCS:.c=.h) $(FW)/boards/rover/le_bytes.h $(FW)/boards/rover/resync_buf.h

ALGO_TEST_SRCS := $(sort $(wildcard $(addprefix $(FW)/tests/,test_losa_*.c test_marker_*.c \
                    test_rover_*.c test_base_*.c test_quat*.c)))
ALGO_TESTS := $(patsubst $(FW)/tests/%.c,$(BUILD)/native/algo_tests/%,$(ALGO_TEST_SRCS))
C_TESTS += $(ALGO_TESTS)

$(ALGO_TESTS): $(BUILD)/native/algo_tests/%: $(FW)/tests/%.c $(ALGO_SRCS) $(ALGO_HDRS) $(FW)/tests/test_algos.h
	@mkdir -p $(@D)
	$(NATIVE_CC) $(NATIVE_CFLAGS) $(SANITIZE) $(ALGO_INC) -o $@ $< $(ALGO_SRCS) -lm

AWBOARDS_LIB := $(BUILD)/native/libawboards.so
$(AWBOARDS_LIB): $(ALGO_SRCS) $(ALGO_HDRS) $(FW)/bench/awboards_abi.c
	@mkdir -p $(@D)
	$(NATIVE_CC) $(NATIVE_CFLAGS) -O2 -fPIC -shared $(ALGO_INC) -o $@ $(ALGO_SRCS) $(FW)/bench/awboards_abi.c -lm
# Built with the native boards so the Python cross-checks find it (they also build it).
NATIVE_BOARDS += $(AWBOARDS_LIB)

# Callgrind drivers: -O2, no sanitizers, no PIE (absolute addresses for the
# per-instruction profile), no errno from sqrtf (an M4 build has none either), no
# vectorisation (every float operation stays one scalar SSE instruction to count).
ALGO_BENCH_DRIVERS := $(BUILD)/native/algo_bench/bench_losa_frame $(BUILD)/native/algo_bench/bench_marker_step
$(BUILD)/native/algo_bench/%: $(FW)/bench/%.c $(ALGO_SRCS) $(ALGO_HDRS)
	@mkdir -p $(@D)
	$(NATIVE_CC) -std=c11 -O2 -g -fno-math-errno -fno-tree-vectorize -no-pie -fno-pie $(ALGO_INC) \
	  -o $@ $< $(ALGO_SRCS) -lm

ALGO_ARM_OBJS := $(patsubst $(FW)/%.c,$(BUILD)/teensy32/algos/%.o,$(ALGO_SRCS))
$(BUILD)/teensy32/algos/%.o: $(FW)/%.c $(ALGO_HDRS)
	@mkdir -p $(@D)
	$(ARM_CC) $(ARM_CFLAGS) $(ALGO_INC) -c $< -o $@

.PHONY: algo-tests awboards algo-bench algo-arm
algo-tests: $(ALGO_TESTS)
	@set -e; for t in $(ALGO_TESTS); do echo "run $${t#$(ROOT)/}"; $$t; done
awboards: $(AWBOARDS_LIB)
algo-bench: $(ALGO_BENCH_DRIVERS)
algo-arm: $(ALGO_ARM_OBJS)
