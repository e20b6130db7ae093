# fuzz.mk — libFuzzer targets (clang, ASan + UBSan), one per byte-stream parser:
#
#   build/fuzz/fuzz_decoder   the airwake link decoder (common/aw_frame.c); its rule is
#                             in protocol.mk (`make -C firmware proto-fuzz`)
#   build/fuzz/fuzz_vn200     the VectorNav binary-output parser (boards/rover/vn200.c)
#   build/fuzz/fuzz_sbp       the Swift Binary Protocol parser (boards/rover/sbp.c)
#
# `make test` runs each for >= 10^6 inputs (tests/link/test_fuzz_smoke.py). Longer runs
# with a corpus kept in build/fuzz/corpus/<target>, seeded by fuzz/make_seeds.py from the
# golden vectors and synthetic VN200/SBP packets:
#   make -C firmware fuzz-run FUZZ_TIME=600 [FUZZ_JOBS=2]
# A broken invariant or sanitizer report leaves build/fuzz/crash-* (re-run it with
# build/fuzz/fuzz_<target> build/fuzz/crash-<hash>).

FUZZ_CC ?= clang
FUZZ_CFLAGS := -std=c11 -g -O1 -Wall -Wextra -Werror -fsanitize=fuzzer,address,undefined \
               -fno-sanitize-recover=all -fno-omit-frame-pointer
# CMP tracing (libFuzzer's hint for magic values) costs these byte-at-a-time parsers 5x
# in exec/s for no coverage gain (the seeds and the targets' recipe half already make
# valid packets): off by default, FUZZ_TRACE_CMP=1 puts it back for long campaigns.
FUZZ_TRACE_CMP ?= 0
FUZZ_PARSER_CFLAGS := $(FUZZ_CFLAGS) $(if $(filter 1,$(FUZZ_TRACE_CMP)),,-fno-sanitize-coverage=trace-cmp)
FUZZ_PARSER_TARGETS := $(BUILD)/fuzz/fuzz_vn200 $(BUILD)/fuzz/fuzz_sbp
FUZZ_TARGETS := $(BUILD)/fuzz/fuzz_decoder $(FUZZ_PARSER_TARGETS)
FUZZ_TIME ?= 600
FUZZ_JOBS ?= 1
PYTHON3 ?= python3

$(BUILD)/fuzz/fuzz_decoder: $(FW)/fuzz/fuzz_util.h

$(FUZZ_PARSER_TARGETS): $(BUILD)/fuzz/%: $(FW)/fuzz/%.c $(FW)/fuzz/fuzz_util.h \
		$(ALGO_SRCS_parsers) $(ALGO_HDRS) $(FW)/mk/fuzz.mk
	@mkdir -p $(@D)
	$(FUZZ_CC) $(FUZZ_PARSER_CFLAGS) $(ALGO_INC) -o $@ $< $(ALGO_SRCS_parsers)

.PHONY: fuzz fuzz-seeds fuzz-run
fuzz: $(FUZZ_TARGETS)

fuzz-seeds:
	$(PYTHON3) $(FW)/fuzz/make_seeds.py $(BUILD)/fuzz/corpus

fuzz-run: $(FUZZ_TARGETS) fuzz-seeds
	@set -e; for t in $(notdir $(FUZZ_TARGETS)); do \
	  echo "fuzz $$t for $(FUZZ_TIME) s"; \
	  (cd $(BUILD)/fuzz && ./$$t -max_total_time=$(FUZZ_TIME) -jobs=$(FUZZ_JOBS) \
	     -workers=$(FUZZ_JOBS) -print_final_stats=1 corpus/$$t); \
	done
