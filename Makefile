# kelp: plain GNU make. See README.md for the targets.
#
# Source layout rules (wildcards, so a new module needs no Makefile edit):
#   core (libkelp_core.a): src/<module>/*.c           -- no malloc, no I/O, no clocks
#   edge (libkelp.a):      src/<module>/edge/*.c, src/app/*.c (the app runner), generated lcmtypes
#   apps:                  apps/<name>/*.c   -> build/bin/<name>
#   core unit tests:       test/check_*.c    (each exports Suite *kelp_<x>_suite(void))
#   edge unit tests:       test/edge/check_*.c
#   integration tests:     test/integration/*.sh (run in a private network namespace)
#   fuzz targets:          fuzz/fuzz_*.c     (LLVMFuzzerTestOneInput)
#   benchmarks:            bench/bench_*.c, bench/run.sh

SHELL      := /bin/bash
# build in parallel unless the caller chose (-jN on the command line wins)
ifeq ($(filter -j%,$(MAKEFLAGS)),)
MAKEFLAGS  += -j$(shell nproc 2>/dev/null || echo 2)
endif
CC         ?= cc
ifeq ($(origin CC),default)
CC         := gcc
endif
AR         ?= ar
BUILD      ?= build
PREFIX     ?= /usr/local
DESTDIR    ?=
VERSION    := 0.1.0
FUZZ_SECONDS ?= 20
ARCH       ?= aarch64

WARN     := -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes \
            -Wpointer-arith -Wformat=2 -Wvla -Wundef
OPT      ?= -O2 -g
CSTD     := -std=c11 -D_DEFAULT_SOURCE -D_GNU_SOURCE
CPPFLAGS += -Iinclude -I$(BUILD)/gen -DKELP_VERSION='"$(VERSION)"' $(CPPFLAGS_EXTRA)
# position-independent everywhere on the host, so the same objects make the static and the
# shared libraries (firmware and cross builds use their own flags)
CFLAGS   += $(CSTD) $(OPT) $(WARN) -fno-common -fPIC
LCM_CFLAGS := $(shell pkg-config --cflags lcm 2>/dev/null)
# what libkelp (the edge) links against (ncurses: the scope apps' terminal tables, src/app/term.c);
# apps add cairo (kelp-plot)
EDGE_LIBS := $(shell pkg-config --libs lcm 2>/dev/null) -lexpat -lmbedtls -lmbedx509 -lmbedcrypto \
            -lserialport -lm -lpthread -lutil $(shell pkg-config --libs ncurses 2>/dev/null || echo -lncurses)
CAIRO_LIBS := $(shell pkg-config --libs cairo 2>/dev/null || echo -lcairo)
MHD_LIBS := $(shell pkg-config --libs libmicrohttpd 2>/dev/null || echo -lmicrohttpd)
EXT_LIBS := $(EDGE_LIBS) $(CAIRO_LIBS)
CHECK_LIBS := $(shell pkg-config --libs check 2>/dev/null)

CORE_SRC := $(filter-out src/app/%,$(sort $(wildcard src/*/*.c)))
# src/plot/edge (cairo rendering) is its own archive, so libkelp does not depend on cairo
PLOT_SRC := $(sort $(wildcard src/plot/edge/*.c))
# src/viewer/edge (libmicrohttpd web server, replay) likewise: libkelp_viewer.a, linked only into kelp-viewer
VIEWER_SRC := $(sort $(wildcard src/viewer/edge/*.c))
EDGE_SRC := $(filter-out $(PLOT_SRC) $(VIEWER_SRC),$(sort $(wildcard src/*/edge/*.c) $(wildcard src/app/*.c)))
LCM_DEFS := $(sort $(wildcard lcmtypes/*.lcm))
GEN_DIR  := $(BUILD)/gen
# lcm-gen names the C file <package>_<struct>.c; every type here is in package kelp.
LCM_C    := $(patsubst lcmtypes/%.lcm,$(GEN_DIR)/kelp_%.c,$(LCM_DEFS))
LCM_H    := $(LCM_C:.c=.h)

CORE_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(CORE_SRC))
EDGE_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(EDGE_SRC)) $(patsubst %.c,$(BUILD)/obj/%.o,$(LCM_C))
PLOT_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(PLOT_SRC))
VIEWER_OBJ := $(patsubst %.c,$(BUILD)/obj/%.o,$(VIEWER_SRC))
APPS     := $(notdir $(patsubst %/,%,$(sort $(dir $(wildcard apps/*/*.c)))))
APP_BINS := $(addprefix $(BUILD)/bin/,$(APPS))
SCRIPTS  := $(notdir $(wildcard tools/kelp-*))

CORE_TESTS := $(filter-out test/check_main.c,$(sort $(wildcard test/check_*.c)))
EDGE_TESTS := $(sort $(wildcard test/edge/check_*.c))
FAKES      := $(sort $(wildcard test/fakes/*.c))
FUZZERS    := $(patsubst fuzz/%.c,%,$(sort $(wildcard fuzz/fuzz_*.c)))
BENCHES    := $(patsubst bench/%.c,$(BUILD)/bench/%,$(sort $(wildcard bench/bench_*.c)))

LIBCORE := $(BUILD)/libkelp_core.a
LIBEDGE := $(BUILD)/libkelp.a
LIBPLOT := $(BUILD)/libkelp_plot.a
LIBVIEWER := $(BUILD)/libkelp_viewer.a
SOMAJOR := $(firstword $(subst ., ,$(VERSION)))
SOCORE  := $(BUILD)/libkelp_core.so.$(VERSION)
SOEDGE  := $(BUILD)/libkelp.so.$(VERSION)
SOPLOT  := $(BUILD)/libkelp_plot.so.$(VERSION)
SOVIEWER := $(BUILD)/libkelp_viewer.so.$(VERSION)

.PHONY: all deps test unit integration conformance check-alloc firmware cross asan lint fuzz bench install \
        demo demo-xrelay spy-jar clean tests-bin unit-noerrmsg asan-build asan-test asan-unit asan-it
.DEFAULT_GOAL := all

all: $(LIBCORE) $(LIBEDGE) $(LIBPLOT) $(LIBVIEWER) $(SOCORE) $(SOEDGE) $(SOPLOT) $(SOVIEWER) $(APP_BINS) scripts

deps:
	@scripts/deps.sh build

# ---------------------------------------------------------------- generated lcmtypes
.SECONDARY: $(LCM_C) $(LCM_H)
$(GEN_DIR)/kelp_%.c $(GEN_DIR)/kelp_%.h: lcmtypes/%.lcm
	@mkdir -p $(GEN_DIR)
	lcm-gen -c --c-cpath $(GEN_DIR) --c-hpath $(GEN_DIR) $<

# ---------------------------------------------------------------- objects
$(BUILD)/obj/%.o: %.c | $(LCM_H)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -MMD -MP -c $< -o $@

# edge objects and generated code see LCM/glib headers; generated code is not ours, relax warnings
$(patsubst %.c,$(BUILD)/obj/%.o,$(EDGE_SRC)): CPPFLAGS += $(LCM_CFLAGS)
# generated code: not ours, so no warnings and no sanitizers (LCM 1.3.1 memcpy(NULL, 0) trips UBSan)
$(BUILD)/obj/$(GEN_DIR)/%.o: CFLAGS := $(CSTD) -O2 -g -w -fPIC
$(BUILD)/obj/$(GEN_DIR)/%.o: CPPFLAGS += $(LCM_CFLAGS)

$(LIBCORE): $(CORE_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && $(AR) rcs $@ $^

$(LIBEDGE): $(EDGE_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && $(AR) rcs $@ $^

$(LIBPLOT): $(PLOT_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && $(AR) rcs $@ $^
$(PLOT_OBJ): CPPFLAGS += $(shell pkg-config --cflags cairo 2>/dev/null)

$(LIBVIEWER): $(VIEWER_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && $(AR) rcs $@ $^
$(VIEWER_OBJ): CPPFLAGS += $(shell pkg-config --cflags libmicrohttpd 2>/dev/null)

# shared libraries with sonames (libkelp_core.so.0, libkelp.so.0, libkelp_plot.so.0,
# libkelp_viewer.so.0) and the usual links; each names what it needs (--no-undefined)
# $(call SO_RULE,name,objects,prerequisite libraries,link arguments)
define SO_RULE
$(BUILD)/$(1).so.$(VERSION): $(2) $(3)
	$$(CC) -shared -Wl,-soname,$(1).so.$(SOMAJOR) -Wl,--no-undefined $$(LDFLAGS) -o $$@ $(2) $(4)
	ln -sf $(1).so.$(VERSION) $(BUILD)/$(1).so.$(SOMAJOR) && ln -sf $(1).so.$(SOMAJOR) $(BUILD)/$(1).so
endef
$(eval $(call SO_RULE,libkelp_core,$(CORE_OBJ),,-lm))
$(eval $(call SO_RULE,libkelp,$(EDGE_OBJ),$(SOCORE),-L$(BUILD) -lkelp_core $(EDGE_LIBS)))
$(eval $(call SO_RULE,libkelp_plot,$(PLOT_OBJ),$(SOEDGE),-L$(BUILD) -lkelp -lkelp_core $(CAIRO_LIBS) -lm))
$(eval $(call SO_RULE,libkelp_viewer,$(VIEWER_OBJ),$(SOEDGE),-L$(BUILD) -lkelp -lkelp_core $(MHD_LIBS) -lpthread))

# ---------------------------------------------------------------- apps
define APP_RULE
$(BUILD)/bin/$(1): $(patsubst %.c,$(BUILD)/obj/%.o,$(wildcard apps/$(1)/*.c)) $(if $(filter kelp-viewer,$(1)),$(LIBVIEWER)) $(LIBPLOT) $(LIBEDGE) $(LIBCORE)
	@mkdir -p $$(dir $$@)
	$$(CC) $$(CFLAGS) -o $$@ $$(filter %.o,$$^) $(if $(filter kelp-viewer,$(1)),$(LIBVIEWER)) $(LIBPLOT) $(LIBEDGE) $(LIBCORE) $$(EXT_LIBS)
endef
$(foreach a,$(APPS),$(eval $(call APP_RULE,$(a))))
$(patsubst %.c,$(BUILD)/obj/%.o,$(wildcard apps/*/*.c)): CPPFLAGS += $(LCM_CFLAGS)
# per-app libraries (target-specific, so only that program links them; ncurses is in libkelp's terminal helper)
$(BUILD)/bin/kelp-moos2sql: EXT_LIBS += $(shell pkg-config --libs sqlite3 2>/dev/null || echo -lsqlite3)
$(BUILD)/bin/kelp-viewer: EXT_LIBS += $(MHD_LIBS)

scripts: $(addprefix $(BUILD)/bin/,$(SCRIPTS))
$(BUILD)/bin/kelp-%: tools/kelp-% Makefile
	@mkdir -p $(dir $@)
	sed 's/@KELP_VERSION@/$(VERSION)/g' $< > $@ && chmod +x $@

# ---------------------------------------------------------------- unit tests
# The list of suites is generated from the test sources, so adding a suite needs no edit here.
$(BUILD)/gen/core_suites.h: $(CORE_TESTS) Makefile
	@mkdir -p $(dir $@)
	@grep -ho 'Suite \*kelp_[a-z0-9_]*_suite(void)' $(CORE_TESTS) /dev/null | sed 's/Suite \*\(.*\)(void)/X(\1)/' > $@.tmp; mv $@.tmp $@
$(BUILD)/gen/edge_suites.h: $(EDGE_TESTS) Makefile
	@mkdir -p $(dir $@)
	@grep -ho 'Suite \*kelp_[a-z0-9_]*_suite(void)' $(EDGE_TESTS) /dev/null | sed 's/Suite \*\(.*\)(void)/X(\1)/' > $@.tmp; mv $@.tmp $@

$(BUILD)/test/check_core: test/check_main.c $(CORE_TESTS) $(FAKES) $(BUILD)/gen/core_suites.h $(LIBCORE)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) -Itest $(CFLAGS) -Wno-missing-prototypes -DKELP_SUITES='"core_suites.h"' -DKELP_RUNNER_NAME='"core"' \
	  -o $@ test/check_main.c $(CORE_TESTS) $(FAKES) $(LIBCORE) $(CHECK_LIBS) -lm
# (libkelp_viewer.a: its files.o only, which needs no microhttpd)
$(BUILD)/test/check_edge: test/check_main.c $(EDGE_TESTS) $(FAKES) $(BUILD)/gen/edge_suites.h $(LIBVIEWER) $(LIBPLOT) $(LIBEDGE) $(LIBCORE)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(LCM_CFLAGS) -Itest $(CFLAGS) -Wno-missing-prototypes -DKELP_SUITES='"edge_suites.h"' -DKELP_RUNNER_NAME='"edge"' \
	  -o $@ test/check_main.c $(EDGE_TESTS) $(FAKES) $(LIBVIEWER) $(LIBPLOT) $(LIBEDGE) $(LIBCORE) $(EXT_LIBS) $(CHECK_LIBS)

tests-bin: $(BUILD)/test/check_core $(BUILD)/test/check_edge

unit: tests-bin
	@scripts/run-suites.sh $(BUILD)/test/check_core && scripts/run-suites.sh $(BUILD)/test/check_edge

# the unit tests again with the messages of kelp_diag compiled out (-DKELP_NO_ERRMSG): codes,
# lines and columns must be the same; tests read a message only through kelp_diag_text()
# and compare it under #ifndef KELP_NO_ERRMSG
unit-noerrmsg:
	@$(MAKE) --no-print-directory BUILD=$(BUILD)-noerrmsg CPPFLAGS_EXTRA=-DKELP_NO_ERRMSG tests-bin
	@scripts/run-suites.sh $(BUILD)-noerrmsg/test/check_core && scripts/run-suites.sh $(BUILD)-noerrmsg/test/check_edge

# the conformance suite: recorded runs of the real MOOS-IvP 24.8 apps replayed on kelp
# (test/conformance/run.sh, compare.py; the recordings: test/conformance/moos-ivp-24.8/README.md);
# CONFORMANCE_SCENARIOS="a b" runs a subset
$(BUILD)/test/conform-driver: test/conformance/driver.c $(LIBEDGE) $(LIBCORE)
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(LCM_CFLAGS) $(CFLAGS) -o $@ $< $(LIBEDGE) $(LIBCORE) $(EDGE_LIBS)

conformance: all $(BUILD)/test/conform-driver
	@BUILD=$(abspath $(BUILD)) test/conformance/run.sh $(CONFORMANCE_SCENARIOS)

integration: all spy-jar
	@BUILD=$(abspath $(BUILD)) scripts/run-integration.sh

test: deps-test
	@$(MAKE) --no-print-directory all tests-bin spy-jar
	@scripts/run-tests.sh $(BUILD)
	@$(MAKE) --no-print-directory unit-noerrmsg

deps-test:
	@scripts/deps.sh test

# ---------------------------------------------------------------- checks
check-alloc: $(LIBCORE)
	@scripts/check-alloc.sh $(LIBCORE)

firmware:
	@scripts/firmware.sh

cross:
	@scripts/cross.sh $(ARCH)

# The integration tests that run again under ASan + UBSan (each runs plainly in make test): the
# ones that put bad or hostile input into the apps and their edge code (bad_input, udpm_attack,
# app_faults, launch_faults, the replayed and serial modem paths, the logs), and one short test
# for each app family (bus, field tools, helm, acomms codecs, viewer, bridge). The long,
# sleep-bound variants (acomms_e2e*, encounter, the fleet demo, the 24.8 mission, moos2sql,
# the browser and Xvfb tests) repeat these programs for minutes of simulated time and stay in
# make test only; the core under them runs under ASan in the unit suites (timefaults included)
# and in the fuzz targets. sim_apps and hazards are left out too: under ASan their apps miss a
# heading sample 4.5 s into a turn (sim_apps) or judge a swath from the neighbouring node report
# (hazards); both run plainly in make test. Override with KELP_ASAN_IT="name ...".
KELP_ASAN_IT ?= bad_input udpm_attack app_faults launch_faults bus_burst lcm_log alog_roundtrip alog2rng \
                acomms_handler_replay acomms_handler_serialport acomms_handler_modem modemsim_pty premuscodec \
                general_codec poller dccl_gen commander nodecomms msghandler_scope hostinfo late_registrant \
                communities_isolated contactmgr beacons timerscript helm_basic helm_spawn kelp_ivp_cpa \
                viewer_http bridge_two_hosts pshare_multicast
# asan = asan-build then asan-test (CI builds while the plain tests run)
asan: asan-build
	@$(MAKE) --no-print-directory asan-test

asan-build:
	@$(MAKE) --no-print-directory BUILD=build-asan CC=gcc \
	  OPT="-O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all" \
	  LDFLAGS="-fsanitize=address,undefined" all tests-bin

# Check timeouts x3: ASan runs the CPU-heavy suites (the solver tables) 20-30x slower
ASAN_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 CK_TIMEOUT_MULTIPLIER=3
asan-test:
	@$(ASAN_ENV) KELP_IT_ONLY="$(KELP_ASAN_IT)" scripts/run-tests.sh build-asan
# the two halves, for CI: the unit suites (CPU-bound, no timing marks) and the integration tests
asan-unit:
	@$(ASAN_ENV) scripts/run-suites.sh build-asan/test/check_core && $(ASAN_ENV) scripts/run-suites.sh build-asan/test/check_edge
asan-it:
	@$(ASAN_ENV) KELP_IT_ONLY="$(KELP_ASAN_IT)" BUILD=$(abspath build-asan) scripts/run-integration.sh

lint:
	@LINT_ANALYZER=$(or $(LINT_ANALYZER),deep) scripts/lint.sh

fuzz:
	@FUZZ_SECONDS=$(FUZZ_SECONDS) scripts/fuzz.sh $(FUZZERS)

bench: all
	@scripts/bench.sh $(BUILD)

# the main job: a shoreside and three vehicles (missions/fleet), tracks drawn to build/demo-fleet/fleet.png
demo:
	@scripts/deps.sh build
	@$(MAKE) --no-print-directory all
	@scripts/demo-fleet.sh $(BUILD)

# the pXRelay example mission of seed 004 through the launcher
demo-xrelay:
	@scripts/deps.sh build
	@$(MAKE) --no-print-directory all
	@scripts/demo.sh $(BUILD)

spy-jar: $(BUILD)/kelp_types.jar
$(BUILD)/kelp_types.jar: $(LCM_DEFS)
	@rm -rf $(BUILD)/java && mkdir -p $(BUILD)/java/src $(BUILD)/java/classes
	lcm-gen -j --jpath $(BUILD)/java/src $(LCM_DEFS)
	javac -nowarn -cp /usr/share/java/lcm.jar -d $(BUILD)/java/classes $$(find $(BUILD)/java/src -name '*.java')
	jar cf $@ -C $(BUILD)/java/classes .

# kelp_types.jar (for kelp-spy) too when a JDK is there; scripts/install.sh says so when not
install: all $(if $(shell command -v javac 2>/dev/null),spy-jar)
	@PREFIX=$(PREFIX) DESTDIR=$(DESTDIR) VERSION=$(VERSION) scripts/install.sh $(BUILD)

clean:
	rm -rf build build-asan build-cross-* build-fw build-fuzz

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)
