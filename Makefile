# SPDX-License-Identifier: MIT
# ggrt -- a Whitted-style ray tracer as a C99 library, and its CLI.
#
#   make                 build/libggrt.a, build/libggrt.so, build/ggrt
#   make check           install missing Debian packages, then run every test
#                        twice: -O2 and ASan+UBSan (see tests/run-tests.sh)
#   make demo            install missing packages, render the default scene
#   make install         PREFIX=/usr/local DESTDIR= (header, libs, ggrt.pc, CLI, man page)
#   make fuzz            libFuzzer (clang) on tests/fuzz/*, FUZZ_SECONDS=60 each
#   make bench-optics    ns per call of the refraction variants
#
# Objects go to $(BUILD) (default build/); BUILD=dir keeps separate trees.

VERSION       = 0.1.0
VERSION_MAJOR = 0

PREFIX     ?= /usr/local
EXEC_PREFIX ?= $(PREFIX)
LIBDIR     ?= $(EXEC_PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
BINDIR     ?= $(EXEC_PREFIX)/bin
MANDIR     ?= $(PREFIX)/share/man
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
DESTDIR    ?=

BUILD   ?= build
CC      ?= cc
CFLAGS  ?= -O2 -g
LDFLAGS ?=
INSTALL ?= install

# Flags for our code. Users' CFLAGS add to these; they cannot turn them off.
# -Werror only where the project builds itself (make check, CI): a user's
# plain `make` on another compiler should not fail on a new warning.
GG_WERROR ?=
GG_WARN   = -std=c99 -Wall -Wextra -pedantic -Wshadow -Wstrict-prototypes $(GG_WERROR)
GG_CPPFLAGS = -D_POSIX_C_SOURCE=200809L -Iinclude -MMD -MP

# Image I/O is the only part that touches libpng and OpenEXR's C core. Their
# headers come in with -isystem: OpenEXR's use anonymous unions, which
# -pedantic -Werror would reject.
PNG_CFLAGS := $(patsubst -I%,-isystem %,$(shell pkg-config --cflags libpng 2>/dev/null))
PNG_LIBS   := $(shell pkg-config --libs libpng 2>/dev/null || echo -lpng16)
EXR_CFLAGS := -isystem /usr/include/OpenEXR
EXR_LIBS   := -lOpenEXRCore
IMG_LIBS    = $(PNG_LIBS) $(EXR_LIBS)
SYS_LIBS    = -lm -lpthread

# `ggrt serve` (cli/serve*.c, the page in cli/web/) is built on GNU
# libmicrohttpd, in the CLI only: the library never links it. SERVE=auto
# (default) builds it when pkg-config finds libmicrohttpd, SERVE=1 insists,
# SERVE=0 leaves it out; without it `ggrt serve` says it is not built in.
SERVE ?= auto
ifeq ($(SERVE),auto)
SERVE_ON := $(shell pkg-config --exists libmicrohttpd 2>/dev/null && echo 1)
else ifeq ($(SERVE),1)
SERVE_ON := 1
endif
ifeq ($(SERVE_ON),1)
SERVE_CPPFLAGS := -DGG_SERVE \
  $(patsubst -I%,-isystem %,$(shell pkg-config --cflags libmicrohttpd 2>/dev/null))
SERVE_LIBS := $(shell pkg-config --libs libmicrohttpd 2>/dev/null || echo -lmicrohttpd)
endif
WEB_SRC := $(sort $(wildcard cli/web/*.html cli/web/*.css cli/web/*.js))

# The library's layers, bottom to top (docs/internals.md). lib/L is compiled
# with include paths for the layers in L_SEES only -- itself and layers below
# it -- so an include of a higher layer does not compile (tests/layers.sh
# checks it). imageio is the only layer built with libpng and OpenEXR flags.
LAYERS        = core optics image implicit geom scene render load imageio
core_SEES     = core
optics_SEES   = core optics
image_SEES    = core image
implicit_SEES = core implicit
geom_SEES     = core implicit geom
scene_SEES    = core image implicit geom scene
render_SEES   = core optics image implicit geom scene render
load_SEES     = core image implicit geom scene load
imageio_SEES  = core image load imageio
imageio_CFLAGS = $(PNG_CFLAGS) $(EXR_CFLAGS)
layer_inc     = $(foreach l,$($(1)_SEES),-Ilib/$(l))
ALL_LAYER_INC = $(LAYERS:%=-Ilib/%)

LIB_SRC  := $(sort $(wildcard $(LAYERS:%=lib/%/*.c)))
LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o)
# Two archives from one set of objects: libggrt (everything) and libggrt-core
# (no image files: nothing of libpng or OpenEXR). Each has its own default
# texture reader (lib/load/load.h explains the pair).
IO_OBJ   := $(filter $(BUILD)/lib/imageio/%,$(LIB_OBJ))
NOREADER_OBJ := $(BUILD)/lib/load/reader_none.o
FULL_OBJ := $(filter-out $(NOREADER_OBJ),$(LIB_OBJ))
CORE_OBJ := $(filter-out $(IO_OBJ),$(LIB_OBJ))
CLI_SRC  := $(sort $(wildcard cli/*.c))
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o) $(if $(SERVE_ON),$(BUILD)/cli/web_assets.o)
TEST_SRC := $(sort $(wildcard tests/test_*.c))
TEST_BIN := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
TESTUTIL_OBJ := $(BUILD)/tests/testutil.o
FUZZ_SRC := $(sort $(wildcard tests/fuzz/fuzz_*.c))
REPLAY_BIN := $(FUZZ_SRC:tests/fuzz/fuzz_%.c=$(BUILD)/tests/replay_%)
BENCH_SRC := $(sort $(wildcard bench/*.c))
BENCH_BIN := $(BENCH_SRC:bench/%.c=$(BUILD)/bench/%)
EXAMPLE_SRC := $(sort $(wildcard examples/*.c))

STATIC = $(BUILD)/libggrt.a
CORE_STATIC = $(BUILD)/libggrt-core.a
SONAME = libggrt.so.$(VERSION_MAJOR)
SHARED = $(BUILD)/libggrt.so.$(VERSION)
CLI    = $(BUILD)/ggrt

.PHONY: all lib cli check test tests deps demo install uninstall installcheck \
        clean fuzz bench examples format pc layers FORCE
.DEFAULT_GOAL := all
.SECONDARY:

all: lib cli
lib: $(STATIC) $(CORE_STATIC) $(SHARED) $(BUILD)/libggrt.so
cli: $(CLI)

define layer_rule
$$(BUILD)/lib/$(1)/%.o: lib/$(1)/%.c
	@mkdir -p $$(@D)
	$$(CC) $$(GG_CPPFLAGS) -DGG_BUILDING $$(call layer_inc,$(1)) $$($(1)_CFLAGS) $$(GG_WARN) \
	  $$(CFLAGS) -fPIC -fvisibility=hidden -c $$< -o $$@
endef
$(foreach l,$(LAYERS),$(eval $(call layer_rule,$(l))))

# For tests/layers.sh: each layer's include flags, one line a layer.
layers:
	@$(foreach l,$(LAYERS),echo "$(l): $(call layer_inc,$(l))";)

$(STATIC): $(FULL_OBJ)
	@mkdir -p $(@D)
	rm -f $@
	$(AR) rcs $@ $^

$(CORE_STATIC): $(CORE_OBJ)
	@mkdir -p $(@D)
	rm -f $@
	$(AR) rcs $@ $^

$(SHARED): $(FULL_OBJ)
	$(CC) -shared -Wl,-soname,$(SONAME) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(IMG_LIBS) $(SYS_LIBS)

$(BUILD)/libggrt.so: $(SHARED)
	ln -sf libggrt.so.$(VERSION) $(BUILD)/$(SONAME)
	ln -sf libggrt.so.$(VERSION) $@

# The CLI sees only the public header (no -Ilib): it is a client of the API.
$(BUILD)/cli/%.o: cli/%.c
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(SERVE_CPPFLAGS) $(GG_WARN) $(CFLAGS) -c $< -o $@

# Whether serve is built in: a file that changes only when that does, so
# that switching SERVE rebuilds the objects that depend on it.
$(BUILD)/cli/serve.flag: FORCE
	@mkdir -p $(@D)
	@[ "`cat $@ 2>/dev/null`" = "serve=$(SERVE_ON)" ] || echo "serve=$(SERVE_ON)" > $@
$(BUILD)/cli/cmd_serve.o $(patsubst cli/%.c,$(BUILD)/cli/%.o,$(wildcard cli/serve_*.c)): \
  $(BUILD)/cli/serve.flag
FORCE:

# The page, compiled into the binary (no files read at run time).
$(BUILD)/cli/web_assets.c: $(WEB_SRC) cli/web/embed.sh
	@mkdir -p $(@D)
	sh cli/web/embed.sh $(WEB_SRC) > $@.tmp && mv $@.tmp $@
$(BUILD)/cli/web_assets.o: $(BUILD)/cli/web_assets.c
	$(CC) $(GG_CPPFLAGS) $(SERVE_CPPFLAGS) -Icli $(GG_WARN) $(CFLAGS) -c $< -o $@

$(CLI): $(CLI_OBJ) $(STATIC)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $(CLI_OBJ) $(STATIC) $(IMG_LIBS) $(SERVE_LIBS) $(SYS_LIBS)

# Tests may look inside (every layer) and link the static archive.
$(BUILD)/tests/%.o: tests/%.c
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(ALL_LAYER_INC) -Itests $(GG_WARN) $(CFLAGS) -c $< -o $@

$(BUILD)/tests/test_%: $(BUILD)/tests/test_%.o $(TESTUTIL_OBJ) $(STATIC)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $< $(TESTUTIL_OBJ) $(STATIC) -lcmocka $(IMG_LIBS) $(SYS_LIBS)

# Each fuzz harness also builds with the plain compiler as a corpus replayer.
$(BUILD)/tests/fuzz/%.o: tests/fuzz/%.c
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(ALL_LAYER_INC) -Itests $(GG_WARN) $(CFLAGS) -c $< -o $@

$(BUILD)/tests/replay_%: $(BUILD)/tests/fuzz/fuzz_%.o $(BUILD)/tests/fuzz/replay.o $(STATIC)
	$(CC) $(CFLAGS) $(LDFLAGS) -o $@ $^ $(IMG_LIBS) $(SYS_LIBS)

$(BUILD)/bench/%: bench/%.c $(STATIC)
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(ALL_LAYER_INC) $(GG_WARN) $(CFLAGS) -o $@ $< $(STATIC) $(IMG_LIBS) $(SYS_LIBS)

tests: $(TEST_BIN) $(REPLAY_BIN) $(CLI)

# Run what is built in $(BUILD); `check` runs it twice.
test: tests
	@sh tests/run-tests.sh "$(BUILD)" $(TEST_BIN) -- $(REPLAY_BIN) -- $(CLI)

SAN_FLAGS = -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer

# check: install missing packages, then the plain and the sanitized runs,
# then stage an install and build the examples against it. Recursive makes
# re-read pkg-config once the packages are there.
check: deps
	@sh tests/layers.sh
	@$(MAKE) --no-print-directory test BUILD=$(BUILD)/release GG_WERROR=-Werror
	@$(MAKE) --no-print-directory test BUILD=$(BUILD)/asan CFLAGS="$(SAN_FLAGS)" \
	  LDFLAGS="-fsanitize=address,undefined" GG_WERROR=-Werror
	@$(MAKE) --no-print-directory installcheck BUILD=$(BUILD)/release GG_WERROR=-Werror
	@echo "check: all suites passed (plain, sanitized, installcheck)"

deps:
	@sh scripts/deps.sh

demo: deps
	@$(MAKE) --no-print-directory all
	$(CLI) render examples/scenes/default.nff -o demo.png
	@echo "demo: wrote demo.png"

# --- install -----------------------------------------------------------

$(BUILD)/%.pc: %.pc.in Makefile
	@mkdir -p $(@D)
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(LIBDIR)|' \
	    -e 's|@INCLUDEDIR@|$(INCLUDEDIR)|' -e 's|@VERSION@|$(VERSION)|' $< > $@

# Regenerated every time: PREFIX may differ between calls.
pc:
	@rm -f $(BUILD)/ggrt.pc $(BUILD)/ggrt-core.pc
	@$(MAKE) --no-print-directory $(BUILD)/ggrt.pc $(BUILD)/ggrt-core.pc

install: all pc
	$(INSTALL) -d $(DESTDIR)$(INCLUDEDIR)/ggrt $(DESTDIR)$(LIBDIR) $(DESTDIR)$(PKGCONFIGDIR) \
	  $(DESTDIR)$(BINDIR) $(DESTDIR)$(MANDIR)/man1
	$(INSTALL) -m 644 include/ggrt.h $(DESTDIR)$(INCLUDEDIR)/
	$(INSTALL) -m 644 include/ggrt/*.h $(DESTDIR)$(INCLUDEDIR)/ggrt/
	$(INSTALL) -m 644 $(STATIC) $(CORE_STATIC) $(DESTDIR)$(LIBDIR)/
	$(INSTALL) -m 755 $(SHARED) $(DESTDIR)$(LIBDIR)/
	ln -sf libggrt.so.$(VERSION) $(DESTDIR)$(LIBDIR)/$(SONAME)
	ln -sf libggrt.so.$(VERSION) $(DESTDIR)$(LIBDIR)/libggrt.so
	$(INSTALL) -m 644 $(BUILD)/ggrt.pc $(BUILD)/ggrt-core.pc $(DESTDIR)$(PKGCONFIGDIR)/
	$(INSTALL) -m 755 $(CLI) $(DESTDIR)$(BINDIR)/
	$(INSTALL) -m 644 docs/ggrt.1 $(DESTDIR)$(MANDIR)/man1/

uninstall:
	rm -f $(DESTDIR)$(INCLUDEDIR)/ggrt.h $(DESTDIR)$(LIBDIR)/libggrt.a \
	  $(DESTDIR)$(LIBDIR)/libggrt-core.a $(DESTDIR)$(PKGCONFIGDIR)/ggrt-core.pc \
	  $(DESTDIR)$(LIBDIR)/libggrt.so $(DESTDIR)$(LIBDIR)/$(SONAME) \
	  $(DESTDIR)$(LIBDIR)/libggrt.so.$(VERSION) $(DESTDIR)$(PKGCONFIGDIR)/ggrt.pc \
	  $(DESTDIR)$(BINDIR)/ggrt $(DESTDIR)$(MANDIR)/man1/ggrt.1
	rm -rf $(DESTDIR)$(INCLUDEDIR)/ggrt

# Stage an install under $(BUILD)/stage with PREFIX=/usr and build and run
# every example against it through pkg-config, as a user would.
STAGE = $(abspath $(BUILD))/stage
installcheck: $(SHARED) $(BUILD)/libggrt.so
	@nm -D --defined-only $(SHARED) >/dev/null || { echo "installcheck: cannot read $(SHARED)"; exit 1; }
	@bad=$$(nm -D --defined-only $(SHARED) | awk '{print $$3}' | grep -v '^gg[A-Z]'); \
	  if [ -n "$$bad" ]; then echo "installcheck: libggrt.so exports internal symbols: $$bad"; exit 1; fi; \
	  echo "installcheck: libggrt.so exports $$(nm -D --defined-only $(SHARED) | wc -l) symbols, all public gg*"
	@rm -rf $(STAGE)
	@$(MAKE) --no-print-directory install DESTDIR=$(STAGE) PREFIX=/usr >/dev/null
	@PKG_CONFIG_SYSROOT_DIR=$(STAGE) PKG_CONFIG_PATH=$(STAGE)/usr/lib/pkgconfig \
	  $(MAKE) --no-print-directory examples EXAMPLE_OUT=$(abspath $(BUILD))/examples
	@for e in $(EXAMPLE_SRC:examples/%.c=%); do \
	  (cd $(abspath $(BUILD))/examples && LD_LIBRARY_PATH=$(STAGE)/usr/lib ./$$e >$$e.log 2>&1) \
	    || { echo "installcheck: example $$e failed:"; cat $(abspath $(BUILD))/examples/$$e.log; exit 1; }; \
	  echo "installcheck: example $$e ran against the staged install"; \
	done
	@PKG_CONFIG_SYSROOT_DIR=$(STAGE) PKG_CONFIG_PATH=$(STAGE)/usr/lib/pkgconfig; \
	  export PKG_CONFIG_SYSROOT_DIR PKG_CONFIG_PATH; out=$(abspath $(BUILD))/examples; \
	  $(CC) -std=c99 -O2 -static -o $$out/core_static_static examples/core_static.c \
	    `pkg-config --static --cflags --libs ggrt-core` \
	    || { echo "installcheck: static link against libggrt-core failed"; exit 1; }; \
	  if readelf -d $$out/core_static_static | grep -q NEEDED; then \
	    echo "installcheck: core_static_static needs shared libraries"; exit 1; fi; \
	  (cd $$out && ./core_static_static $(CURDIR)/examples/scenes/default.nff core_static.ppm 64x48 >/dev/null) \
	    || { echo "installcheck: the static core example failed"; exit 1; }; \
	  echo "installcheck: examples/core_static.c linked with -static against libggrt-core" \
	    "(`pkg-config --static --libs ggrt-core`) and rendered default.nff"

# Examples build against an installed libggrt found by pkg-config.
EXAMPLE_OUT ?= $(BUILD)/examples
examples:
	@mkdir -p $(EXAMPLE_OUT)
	@for e in $(EXAMPLE_SRC:examples/%.c=%); do \
	  echo "$(CC) examples/$$e.c \`pkg-config --cflags --libs ggrt\`"; \
	  $(CC) -std=c99 -Wall -Wextra -pedantic -Werror -O2 -o $(EXAMPLE_OUT)/$$e examples/$$e.c \
	    `pkg-config --cflags --libs ggrt` || exit 1; \
	done

# --- fuzzing and benchmarks ---------------------------------------------

FUZZ_SECONDS ?= 60
FUZZ_CC ?= clang
fuzz:
	@mkdir -p $(BUILD)/fuzz
	@for f in $(FUZZ_SRC:tests/fuzz/fuzz_%.c=%); do \
	  $(FUZZ_CC) $(GG_CPPFLAGS) $(ALL_LAYER_INC) -Itests -std=c99 -g -O1 \
	    -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
	    $(PNG_CFLAGS) $(EXR_CFLAGS) -o $(BUILD)/fuzz/fuzz_$$f tests/fuzz/fuzz_$$f.c $(LIB_SRC) \
	    $(IMG_LIBS) $(SYS_LIBS) || exit 1; \
	  mkdir -p $(BUILD)/fuzz/corpus_$$f; \
	  $(BUILD)/fuzz/fuzz_$$f -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 \
	    -artifact_prefix=$(BUILD)/fuzz/ \
	    $(BUILD)/fuzz/corpus_$$f tests/fuzz/corpus/$$f || exit 1; \
	done

bench: $(BENCH_BIN)
	@for b in $(BENCH_BIN); do $$b || exit 1; done

# The ray-tree recorder's cost when switched off: the same renders with
# this library and with one built without the recorder, alternated.
bench-trace: $(BUILD)/bench/bench_render
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/norec CFLAGS="$(CFLAGS) -DGG_NO_RECORDER" \
	  $(BUILD)/norec/bench/bench_render >/dev/null
	@sh bench/trace_overhead.sh $(BUILD)/bench/bench_render $(BUILD)/norec/bench/bench_render

bench-%: $(BUILD)/bench/bench_%
	$<

format:
	clang-format -i include/*.h include/ggrt/*.h lib/*/*.c lib/*/*.h cli/*.c cli/*.h tests/*.c \
	  tests/*.h tests/fuzz/*.c bench/*.c examples/*.c

clean:
	rm -rf $(BUILD)

-include $(wildcard $(BUILD)/lib/*/*.d $(BUILD)/cli/*.d $(BUILD)/tests/*.d $(BUILD)/tests/fuzz/*.d)
