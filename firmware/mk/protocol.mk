# protocol.mk — the wire protocol's C code (common/aw_frame.c, generated aw_messages.c).
#
#   build/tests/test_proto_*      C tests under ASan/UBSan (added to C_TESTS)
#   build/native/libawproto.so    -O2 shared library for the Python cross-language tests
#   build/native/bench_proto      -O2 decoder benchmark (airwake bench, callgrind)
#   build/obj/proto-arm/*.o       the same sources with arm-none-eabi-gcc, ARM_CFLAGS:
#                                 built before the C tests so `make test` proves they compile
#   build/fuzz/fuzz_decoder       libFuzzer target (clang); `make -C firmware proto-fuzz`

PROTO_SRCS := $(FW)/common/aw_frame.c $(FW)/common/aw_messages.c
PROTO_HDRS := $(FW)/common/aw_frame.h $(FW)/common/aw_messages.h $(FW)/common/aw_wire.h
PROTO_INC := -I$(FW)/common -I$(FW)/tests
PROTO_TEST_NAMES := test_proto_framing test_proto_vectors test_proto_corruption
PROTO_TESTS := $(addprefix $(BUILD)/tests/,$(PROTO_TEST_NAMES))
PROTO_ARM_OBJS := $(patsubst $(FW)/common/%.c,$(BUILD)/obj/proto-arm/%.o,$(PROTO_SRCS))
PROTO_LIB := $(BUILD)/native/libawproto.so
PROTO_BENCH := $(BUILD)/native/bench_proto
PROTO_FUZZ := $(BUILD)/fuzz/fuzz_decoder
PROTO_OPT_CFLAGS := $(filter-out -O1 -g,$(NATIVE_CFLAGS)) -O2

C_TESTS += $(PROTO_TESTS)

$(BUILD)/obj/proto-arm/%.o: $(FW)/common/%.c $(PROTO_HDRS)
	@mkdir -p $(@D)
	$(ARM_CC) $(ARM_CFLAGS) -Wconversion -Wshadow -I$(FW)/common -c $< -o $@

$(BUILD)/tests/test_proto_%: $(FW)/tests/test_proto_%.c $(PROTO_SRCS) $(PROTO_HDRS) \
		$(FW)/tests/test_proto_util.h $(FW)/tests/test_proto_vectors.h | $(PROTO_ARM_OBJS)
	@mkdir -p $(@D)
	$(NATIVE_CC) $(NATIVE_CFLAGS) $(SANITIZE) $(PROTO_INC) -o $@ $< $(PROTO_SRCS) -lm

$(PROTO_LIB): $(FW)/tests/test_proto_ffi.c $(PROTO_SRCS) $(PROTO_HDRS)
	@mkdir -p $(@D)
	$(NATIVE_CC) $(PROTO_OPT_CFLAGS) -fPIC -shared $(PROTO_INC) -o $@ $< $(PROTO_SRCS)

$(PROTO_BENCH): $(FW)/tests/test_proto_bench.c $(PROTO_SRCS) $(PROTO_HDRS) $(FW)/tests/test_proto_util.h
	@mkdir -p $(@D)
	$(NATIVE_CC) $(PROTO_OPT_CFLAGS) -g -fno-inline-functions-called-once $(PROTO_INC) \
		-o $@ $< $(PROTO_SRCS) -lm

$(PROTO_FUZZ): $(FW)/fuzz/fuzz_decoder.c $(PROTO_SRCS) $(PROTO_HDRS)
	@mkdir -p $(@D)
	clang -std=c11 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
		$(PROTO_INC) -o $@ $< $(PROTO_SRCS)

.PHONY: proto proto-lib proto-bench proto-arm proto-fuzz
proto: $(PROTO_TESTS) $(PROTO_LIB) $(PROTO_BENCH)
proto-lib: $(PROTO_LIB)
proto-bench: $(PROTO_BENCH)
proto-arm: $(PROTO_ARM_OBJS)
proto-fuzz: $(PROTO_FUZZ)
