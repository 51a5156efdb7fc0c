# SPDX-License-Identifier: MIT
# ggrt -- a Whitted-style ray tracer as a C99 library, and its CLI.
#
#   make                 build/libggrt.a, build/libggrt.so, build/ggrt and the
#                        example plugin build/libtextbook_refract.so (ggrt optics check)
#   make check           install the missing Debian packages the tests need, then
#                        check the layers and the path names in docs and comments
#                        (tests/build/layers.sh, tests/build/paths.sh), run every
#                        suite -O3 and under ASan+UBSan with $(CC), the C suites
#                        again with the other of GCC and clang (CHECK_CC2; CHECK_CC2=
#                        skips), the concurrency tests under ThreadSanitizer (GCC's),
#                        then against an installed copy; CHECK_JOBS at a time (the
#                        suites print TAP, tests/run-tests.sh reads it: see check below)
#   make demo            install the missing packages the build and ggrt serve need,
#                        build, render the default scene
#   make help            the targets and the variables users set
#   make install         PREFIX=/usr/local DESTDIR= (header, libs, ggrt.pc, CLI, man
#                        page, bash completion); a live install (no DESTDIR)
#                        refreshes ldconfig's cache
#   make fuzz            libFuzzer (clang) on tests/fuzz/*, FUZZ_SECONDS=60 each; every
#                        harness runs, a summary at the end (exit 1 if any found something);
#                        FUZZ="obj ply" runs only those
#   make check-browser   ggrt serve's page in headless Chromium (CI runs it after check)
#   scripts/deps.sh      the package groups each of these installs
#   make bench           every bench/bench_*.c program in turn
#   make bench-NAME      one benchmark (prints figures; not a test), NAME one of:
#                        debug, geometry, image, implicit, render: that bench/bench_*.c;
#                        optics    ns and instructions per call of the refraction variants;
#                        mesh      mesh read, BVH build, memory and render speed
#                                  (bench/bench_mesh.c; EMBREE=BIN adds the Embree
#                                  anchor's build times);
#                        trace     the ray-tree recorder's cost when off (bench/trace_overhead.sh);
#                        plan      ggrt plan's cut against equal bands (bench/plan_bench.sh);
#                        serve     requests/s and latency of ggrt serve under N clients
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
# Where bash-completion looks for a command's script (cli/completion.bash,
# installed as "ggrt"; Debian's own packages use /usr/share/...).
BASHCOMPDIR ?= $(PREFIX)/share/bash-completion/completions
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
DESTDIR    ?=
# Run after a live install (no DESTDIR) as root; LDCONFIG= skips it.
LDCONFIG   ?= ldconfig

BUILD   ?= build
CC      ?= cc
# -O3: the same bits as -O2 (every copy keeps IEEE rounding, -ffp-contract=off
# below) and fewer instructions in the traversal and shading loops:
# docs/performance.md, "Optimisation level".
CFLAGS  ?= -O3 -g
LDFLAGS ?=
# GG_EXE_LDFLAGS: flags for the programs' links only, not the shared
# objects' (the sanitizer trees of make check set -no-pie there).
GG_EXE_LDFLAGS ?=
INSTALL ?= install

# Flags for our code. Users' CPPFLAGS and CFLAGS add to these (after them on
# every compile line, so -D_FORTIFY_SOURCE=2 or an -I reaches each object);
# they cannot turn them off.
# -Werror only where the project builds itself (make check, CI): a user's
# plain `make` on another compiler should not fail on a new warning.
GG_WERROR ?=
# Debug information valgrind (3.19, which make check runs) can read: clang
# writes DWARF 5 forms it cannot, so clang builds with -g get DWARF 4.
GG_CLANG := $(if $(shell $(CC) --version 2>/dev/null | grep -i clang),1)
GG_DWARF := $(if $(GG_CLANG),-gdwarf-4)
GG_WARN   = -std=c99 -Wall -Wextra -pedantic -Wshadow -Wstrict-prototypes $(GG_WERROR) \
            $(if $(filter -g%,$(CFLAGS)),$(GG_DWARF))
GG_CPPFLAGS = -D_POSIX_C_SOURCE=200809L -Iinclude -MMD -MP

# PKG_CONFIG: the pkg-config that answers for the libraries built against
# (a cross build's, say aarch64-linux-gnu-pkg-config); every lookup below,
# the examples and installcheck use it.
PKG_CONFIG ?= pkg-config

# Image I/O is the only part that touches libpng and OpenEXR's C core. Their
# headers come in with -isystem: OpenEXR's use anonymous unions, which
# -pedantic -Werror would reject.
PNG_CFLAGS := $(patsubst -I%,-isystem %,$(shell $(PKG_CONFIG) --cflags libpng 2>/dev/null))
PNG_LIBS   := $(shell $(PKG_CONFIG) --libs libpng 2>/dev/null || echo -lpng16)
EXR_CFLAGS := -isystem /usr/include/OpenEXR
EXR_LIBS   := -lOpenEXRCore
IMG_LIBS    = $(PNG_LIBS) $(EXR_LIBS)
SYS_LIBS    = -lm -lpthread

# ggrt serve (cli/serve/) is built with libmicrohttpd when pkg-config finds
# it (-DGG_HAVE_MHD); without it the rest of the CLI builds the same and
# `ggrt serve` says what to install. scripts/deps.sh: group serve.
# ggrt does not link it: `ggrt serve` opens it by the soname read here
# (MHD_SONAME; cli/serve/serve_http.c says why), and only ggrt serve.
MHD_CFLAGS := $(patsubst -I%,-isystem %,$(shell $(PKG_CONFIG) --cflags libmicrohttpd 2>/dev/null))
MHD_LIBS   := $(shell $(PKG_CONFIG) --libs libmicrohttpd 2>/dev/null)
MHD_SONAME := $(if $(MHD_LIBS),$(shell objdump -p "`$(PKG_CONFIG) --variable=libdir libmicrohttpd`/libmicrohttpd.so" \
                2>/dev/null | sed -n 's/^ *SONAME *//p'))
CLI_DEFS   =
CLI_SERVE  =
ifneq ($(MHD_LIBS),)
ifneq ($(wildcard cli/serve/*.c),)
CLI_DEFS   = -DGG_HAVE_MHD $(MHD_CFLAGS) $(if $(MHD_SONAME),-DGG_MHD_SONAME='"$(MHD_SONAME)"')
CLI_SERVE  = mhd $(MHD_SONAME)
endif
endif
# The page served by ggrt serve (cli/serve/web/), compiled into the binary.
WEB_SRC := $(sort $(wildcard cli/serve/web/*.html cli/serve/web/*.css cli/serve/web/*.js))

# The library's layers, bottom to top (docs/internals.md). lib/L is compiled
# with include paths for the layers in L_SEES only -- itself and layers below
# it -- so an include of a higher layer does not compile (tests/build/layers.sh
# checks it). imageio is the only layer built with libpng and OpenEXR flags.
LAYERS        = core optics image implicit geom scene render debug load imageio
core_SEES     = core
optics_SEES   = core optics
image_SEES    = core image
implicit_SEES = core implicit
geom_SEES     = core implicit geom
scene_SEES    = core image implicit geom scene
render_SEES   = core optics image implicit geom scene render
debug_SEES    = core optics image implicit geom scene render debug
load_SEES     = core image implicit geom scene load
imageio_SEES  = core image load imageio
imageio_CFLAGS = $(PNG_CFLAGS) $(EXR_CFLAGS)
# The optics functions raise no floating-point exception on finite input
# (tests/unit/optics/test_optics.c test_no_fp_exceptions); clang would otherwise
# evaluate a branch's arithmetic before the branch (an overflow the taken
# path never computes). GCC does not speculate trapping operations.
optics_CFLAGS  = $(if $(GG_CLANG),-ffp-exception-behavior=maytrap)
layer_inc     = $(foreach l,$($(1)_SEES),-Ilib/$(l))

# Per-ISA objects (lib/core/compiler.h, "Per-ISA code"): on x86-64 a library
# object named *_avx.o, *_avx2.o, *_avx512.o or *_fma.o gets that instruction set's
# flags and -DGG_ISA=avx, avx2, avx512 or fma (isa_flags), and only it; the library picks among the
# copies at run time, once (the kernel table, lib/core/cpu.c). Its source is the
# .c of that name, or for one source built for several sets the one ISA_AGAIN
# names: OBJ:SRC compiles SRC once more into OBJ, so no .c includes another.
# Where the compiler does not target x86-64 they compile to nothing
# (CFLAGS=-DGG_NO_ISA does that on x86-64 too).
# -ffp-contract=off everywhere: no compiler (clang contracts by default)
# may fuse a*b+c, so every copy of a kernel rounds the same way.
# The AVX-512 copy uses AVX-512's masks and compress on 256-bit registers
# only (-mprefer-vector-width=256 and GG_MOVE_MAX: no 512-bit code from
# the vectoriser or from inlined copies either): on an Intel Xeon
# (Sapphire Rapids) its few 512-bit instructions made every walk slower
# (docs/performance.md, "AVX-512 copies"; tests/build/isa.sh checks).
# -fno-math-errno in the library: nothing in it reads errno after a libm
# call, so sqrt is one instruction, without the branch to libm that would
# only set errno; the results are the same bits (docs/performance.md,
# "No errno from libm").
GG_MATH = -ffp-contract=off -fno-math-errno
ISA_avx       = -mavx
ISA_avx2      = -mavx -mavx2 -mbmi -mbmi2 -mlzcnt -mpopcnt
ISA_avx512    = $(ISA_avx2) -mfma -mavx512f -mavx512vl -mavx512dq -mavx512bw \
                -mprefer-vector-width=256 $(GG_MOVE_MAX)
# GCC 12 and later: struct copies and clears at most 256 bits wide too
GG_MOVE_MAX  := $(shell $(CC) -mmove-max=256 -mstore-max=256 -x c -c /dev/null -o /dev/null \
                  2>/dev/null && echo -mmove-max=256 -mstore-max=256)
ISA_fma       = -mfma
GG_ISA_X86   := $(if $(filter x86_64-% amd64-%,$(shell $(CC) -dumpmachine 2>/dev/null)),1)
isa_of        = $(if $(GG_ISA_X86),$(strip $(foreach i,avx avx2 avx512 fma,$(if $(filter %_$(i).o,$(1)),$(i)))))
isa_flags     = $(if $(call isa_of,$(1)),$(ISA_$(call isa_of,$(1))) -DGG_ISA=$(call isa_of,$(1)))
ISA_AGAIN     = lib/geom/bvh_avx2.o:lib/geom/bvh_avx.c lib/geom/bvh_avx512.o:lib/geom/bvh_avx.c \
                lib/geom/bvh_count_avx.o:lib/geom/bvh_avx.c lib/geom/bvh_kloop_avx.o:lib/geom/bvh_avx.c \
                lib/geom/bvh_kloop_avx2.o:lib/geom/bvh_avx.c lib/geom/bvh_kloop_avx512.o:lib/geom/bvh_avx.c
# Defines of one object: the counting copy of the AVX walks and the
# kernel loops (bvh_avx.c, `ggrt bench limit`).
OBJ_DEFS_bvh_count_avx.o    = -DGG_TRAV_COUNT
OBJ_DEFS_bvh_kloop_avx.o    = -DGG_TRAV_KLOOP
OBJ_DEFS_bvh_kloop_avx2.o   = -DGG_TRAV_KLOOP
OBJ_DEFS_bvh_kloop_avx512.o = -DGG_TRAV_KLOOP
isa_again_obj = $(foreach p,$(ISA_AGAIN),$(firstword $(subst :, ,$(p))))
ALL_LAYER_INC = $(LAYERS:%=-Ilib/%)

LIB_SRC  := $(sort $(wildcard $(LAYERS:%=lib/%/*.c)))
LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o) $(isa_again_obj:%=$(BUILD)/%)
# Two archives from one set of objects: libggrt (everything) and libggrt-core
# (no image files: nothing of libpng or OpenEXR). Each has its own default
# texture reader (lib/load/load.h explains the pair).
IO_OBJ   := $(filter $(BUILD)/lib/imageio/%,$(LIB_OBJ))
NOREADER_OBJ := $(BUILD)/lib/load/reader_none.o
FULL_OBJ := $(filter-out $(NOREADER_OBJ),$(LIB_OBJ))
CORE_OBJ := $(filter-out $(IO_OBJ),$(LIB_OBJ))
# cli/main.c and one folder per command or group, cli/common/ shared (docs/internals.md).
CLI_SRC  := $(sort $(wildcard cli/*.c cli/*/*.c))
CLI_OBJ  := $(CLI_SRC:%.c=$(BUILD)/%.o) $(if $(CLI_SERVE),$(BUILD)/cli/serve/web_assets.o)
# The cmocka suites: tests/unit/LAYER/ (one layer's code) and tests/api/
# (contracts of every public function); each builds to the same path under
# $(BUILD) (build/tests/unit/geom/test_bvh).
TEST_SRC := $(sort $(wildcard tests/unit/*/test_*.c tests/api/test_*.c))
TEST_BIN := $(TEST_SRC:%.c=$(BUILD)/%)
TESTUTIL_OBJ := $(BUILD)/tests/common/testutil.o
TEST_INC  = $(ALL_LAYER_INC) -Itests/common
# Linked with the portable geom layer (below).
SCALAR_TESTS := $(BUILD)/tests/unit/geom/test_bvh_scalar $(BUILD)/tests/unit/geom/test_packet_scalar
FUZZ_SRC := $(sort $(wildcard tests/fuzz/fuzz_*.c))
REPLAY_BIN := $(FUZZ_SRC:tests/fuzz/fuzz_%.c=$(BUILD)/tests/replay_%)
BENCH_SRC := $(sort $(wildcard bench/*.c))
BENCH_BIN := $(BENCH_SRC:bench/%.c=$(BUILD)/bench/%)
# The optics check's examples are a plug-in library and a fuzz harness,
# not programs: built by their own rules below.
OPTICS_EXAMPLES := examples/textbook_refract.c examples/fuzz_your_refract.c
EXAMPLE_SRC := $(filter-out $(OPTICS_EXAMPLES),$(sort $(wildcard examples/*.c)))

STATIC = $(BUILD)/libggrt.a
CORE_STATIC = $(BUILD)/libggrt-core.a
SONAME = libggrt.so.$(VERSION_MAJOR)
SHARED = $(BUILD)/libggrt.so.$(VERSION)
CLI    = $(BUILD)/ggrt

.PHONY: all help lib cli check test test-tsan tests deps demo install uninstall installcheck \
        clean fuzz bench examples format pc layers FORCE check-browser check-cluster bench-serve \
        bench-plan bench-bin \
        check-layers check-paths check-release check-asan check-cc2 check-cc2-asan check-tsan
.DEFAULT_GOAL := all
.SECONDARY:
# A recipe that fails removes its half-written target.
.DELETE_ON_ERROR:

all: lib cli $(BUILD)/libtextbook_refract.so
lib: $(STATIC) $(CORE_STATIC) $(SHARED) $(BUILD)/libggrt.so
cli: $(CLI)

help:
	@echo 'make [TARGET] [VARIABLE=value...]; details: the comments at the top of Makefile'
	@echo 'targets:'
	@echo '  all            (default) the libraries, ggrt and libtextbook_refract.so in $$(BUILD)'
	@echo '  install        headers, libraries, .pc files, ggrt, ggrt(1); uninstall removes them'
	@echo '  demo           install missing packages, build, render demo.png'
	@echo '  test           build the test programs in $$(BUILD) and run every suite'
	@echo '  check          install missing packages, every suite in every build (long)'
	@echo '  installcheck   the examples and README lines against a staged and a real install'
	@echo '  bench          every bench/bench_*.c program; bench-NAME one benchmark, NAME one of'
	@echo '                 debug geometry image implicit mesh optics render trace plan serve'
	@echo '  examples fuzz check-browser check-cluster format clean'
	@echo 'variables (their values now):'
	@echo '  PREFIX=$(PREFIX) DESTDIR=$(DESTDIR) (staging root)'
	@echo '  LIBDIR=$(LIBDIR) INCLUDEDIR=$(INCLUDEDIR) BINDIR=$(BINDIR) MANDIR=$(MANDIR)'
	@echo '  BASHCOMPDIR=$(BASHCOMPDIR)'
	@echo '  BUILD=$(BUILD) (objects and programs) CC=$(CC) PKG_CONFIG=$(PKG_CONFIG)'
	@echo '  CFLAGS=$(CFLAGS) CPPFLAGS=$(CPPFLAGS) LDFLAGS=$(LDFLAGS) (added to the project'"'"'s)'
	@echo '  LDCONFIG=$(LDCONFIG) (empty: not run) GG_WERROR=$(GG_WERROR) (-Werror: warnings fail)'
	@echo '  GG_NO_DEPS=1: install no packages (check, demo, fuzz...; scripts/deps.sh)'

# A library object of layer $(1) (the folder of $<).
lib_cc = $(CC) $(GG_CPPFLAGS) -DGG_BUILDING $(call layer_inc,$(1)) $($(1)_CFLAGS) $(GG_WARN) \
	  $(call isa_flags,$@) $(OBJ_DEFS_$(notdir $@)) $(CPPFLAGS) $(CFLAGS) $(GG_MATH) -fPIC -fvisibility=hidden -c $< -o $@
define layer_rule
$$(BUILD)/lib/$(1)/%.o: lib/$(1)/%.c
	@mkdir -p $$(@D)
	$$(call lib_cc,$(1))
endef
$(foreach l,$(LAYERS),$(eval $(call layer_rule,$(l))))
# The build's identity, ggBuildId() (lib/core/base.c): "src-" and the
# POSIX cksum (a CRC-32, the same on every machine) of the library's
# sources, names and bytes, so that tiles, reports and plans of two builds
# do not merge (docs/cluster.md). A header under $(BUILD), for base.o.
GG_ID_SRC := $(sort $(wildcard lib/*/*.c lib/*/*.h include/*.h include/ggrt/*.h))
$(BUILD)/lib/core/buildid.h: $(GG_ID_SRC)
	@mkdir -p $(@D)
	@for f in $(GG_ID_SRC); do echo "$$f"; cat "$$f"; done | cksum | \
	  sed 's/^\([0-9]*\).*/#define GG_BUILD_ID "src-\1"/' >$@.tmp && mv $@.tmp $@
$(BUILD)/lib/core/base.o: $(BUILD)/lib/core/buildid.h
$(BUILD)/lib/core/base.o: core_CFLAGS += -I$(BUILD)/lib/core
# ISA_AGAIN: the same source, another object (and flags); also in the
# portable geom build below (scalar_cc).
define isa_again_rule
$$(BUILD)/$(1): $(2)
	@mkdir -p $$(@D)
	$$(call lib_cc,$(word 2,$(subst /, ,$(2))))
$$(BUILD)/scalar/$(1): $(2)
	@mkdir -p $$(@D)
	$$(scalar_cc)
endef
$(foreach p,$(ISA_AGAIN),$(eval $(call isa_again_rule,$(firstword $(subst :, ,$(p))),$(lastword $(subst :, ,$(p))))))
# A build tree older than ISA_AGAIN keeps a dependency file naming the
# source (bvh_avx2.c) an ISA_AGAIN object was once built from: an empty
# rule lets make rebuild the object once (which rewrites that file)
# instead of stopping.
$(foreach p,$(ISA_AGAIN),$(patsubst %.o,%.c,$(firstword $(subst :, ,$(p))))):

# For tests/build/layers.sh: each layer's include flags, one line a layer.
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

# The exports and their version: lib/libggrt.map.
$(SHARED): $(FULL_OBJ) lib/libggrt.map
	$(CC) -shared -Wl,-soname,$(SONAME) -Wl,--version-script=lib/libggrt.map $(CFLAGS) $(LDFLAGS) \
	  -o $@ $(FULL_OBJ) $(IMG_LIBS) $(SYS_LIBS)

$(BUILD)/libggrt.so: $(SHARED)
	ln -sf libggrt.so.$(VERSION) $(BUILD)/$(SONAME)
	ln -sf libggrt.so.$(VERSION) $@

# The CLI sees only the public header (no -Ilib): it is a client of the API.
# Its includes name their folder ("common/cli.h", "serve/serve.h"): -Icli.
CLI_INC = -Icli
$(BUILD)/cli/%.o: cli/%.c
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(CLI_DEFS) $(CLI_INC) $(GG_WARN) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

# Whether serve is built in: a file that changes only when that does, so
# that installing libmicrohttpd (or `make MHD_LIBS=` to leave it out)
# rebuilds the objects that depend on it.
$(BUILD)/cli/serve.flag: FORCE
	@mkdir -p $(@D)
	@[ "`cat $@ 2>/dev/null`" = "serve=$(CLI_SERVE)" ] || echo "serve=$(CLI_SERVE)" > $@
$(patsubst cli/%.c,$(BUILD)/cli/%.o,$(wildcard cli/serve/*.c)): $(BUILD)/cli/serve.flag
FORCE:

# The page, compiled into the binary (nothing is read from disk at run time).
$(BUILD)/cli/serve/web_assets.c: $(WEB_SRC) cli/serve/web/embed.sh
	@mkdir -p $(@D)
	sh cli/serve/web/embed.sh $(WEB_SRC) > $@.tmp && mv $@.tmp $@
$(BUILD)/cli/serve/web_assets.o: $(BUILD)/cli/serve/web_assets.c
	$(CC) $(GG_CPPFLAGS) $(CLI_DEFS) $(CLI_INC) $(GG_WARN) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

# -ldl: `ggrt optics check --lib` (cli/optics/optics_check.c) and `ggrt serve`
# (libmicrohttpd, cli/serve/serve_http.c); the library never loads code.
$(CLI): $(CLI_OBJ) $(STATIC)
	$(CC) $(CFLAGS) $(LDFLAGS) $(GG_EXE_LDFLAGS) -o $@ $(CLI_OBJ) $(STATIC) $(IMG_LIBS) $(SYS_LIBS) -ldl

# Tests may look inside (every layer) and link the static archive.
$(BUILD)/tests/%.o: tests/%.c
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(TEST_INC) $(GG_WARN) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(filter-out $(SCALAR_TESTS),$(TEST_BIN)): %: %.o $(TESTUTIL_OBJ) $(STATIC)
	$(CC) $(CFLAGS) $(LDFLAGS) $(GG_EXE_LDFLAGS) -o $@ $< $(TESTUTIL_OBJ) $(STATIC) -lcmocka $(IMG_LIBS) $(SYS_LIBS)

# test_bvh_scalar and test_packet_scalar run the BVH and packet suites on the
# portable C traversal: the geom layer built a second time with
# GG_BVH_NO_SIMD, linked instead of the library's (explicit objects, no
# archive: nothing depends on link order).
SCALAR_GEOM := $(patsubst $(BUILD)/lib/%,$(BUILD)/scalar/lib/%,$(filter $(BUILD)/lib/geom/%,$(FULL_OBJ)))
scalar_cc = $(CC) $(GG_CPPFLAGS) -DGG_BUILDING -DGG_BVH_NO_SIMD $(call layer_inc,geom) $(GG_WARN) \
	  $(call isa_flags,$@) $(OBJ_DEFS_$(notdir $@)) $(CPPFLAGS) $(CFLAGS) $(GG_MATH) -c $< -o $@
$(BUILD)/scalar/lib/geom/%.o: lib/geom/%.c
	@mkdir -p $(@D)
	$(scalar_cc)

$(SCALAR_TESTS): %: %.o $(TESTUTIL_OBJ) $(FULL_OBJ) $(SCALAR_GEOM)
	$(CC) $(CFLAGS) $(LDFLAGS) $(GG_EXE_LDFLAGS) -o $@ $< $(TESTUTIL_OBJ) $(filter-out $(BUILD)/lib/geom/%,$(FULL_OBJ)) \
	  $(SCALAR_GEOM) -lcmocka $(IMG_LIBS) $(SYS_LIBS)

# Each fuzz harness also builds with the plain compiler as a corpus replayer.
$(BUILD)/tests/fuzz/%.o: tests/fuzz/%.c
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(TEST_INC) $(GG_WARN) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/tests/replay_%: $(BUILD)/tests/fuzz/fuzz_%.o $(BUILD)/tests/fuzz/replay.o $(STATIC)
	$(CC) $(CFLAGS) $(LDFLAGS) $(GG_EXE_LDFLAGS) -o $@ $^ $(IMG_LIBS) $(SYS_LIBS)

# Harnesses of CLI code: NAME:SOURCE for each CLI source a harness tests,
# compiled with it (-Icli); the others link only the library.
FUZZ_CLI = json:cli/render/jdom.c
$(BUILD)/tests/fuzz/fuzz_json.o: TEST_INC += $(CLI_INC)
$(BUILD)/tests/replay_json: $(BUILD)/cli/render/jdom.o

$(BUILD)/bench/%: bench/%.c $(STATIC)
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(ALL_LAYER_INC) $(GG_WARN) $(CPPFLAGS) $(CFLAGS) -o $@ $< $(STATIC) $(IMG_LIBS) $(SYS_LIBS)

# `ggrt optics check` measures this one (tests/cli/t_optics_check.sh); built
# by `make` so that README's `optics check --lib` line works after it.
$(BUILD)/libtextbook_refract.so: examples/textbook_refract.c
	@mkdir -p $(@D)
	$(CC) $(GG_CPPFLAGS) $(GG_WARN) $(CPPFLAGS) $(CFLAGS) -fPIC -shared $(LDFLAGS) -o $@ $< -lm

# examples/fuzz_your_refract.c as a corpus replayer (tests/fuzz/replay.c),
# against ggRefract and against the textbook function (tests/cli/t_optics_check.sh).
YOURFUZZ = $(BUILD)/tests/yourfuzz_ggrefract $(BUILD)/tests/yourfuzz_textbook
YOURFUZZ_CC = $(CC) -D_POSIX_C_SOURCE=200809L -Iinclude $(GG_WARN) $(CPPFLAGS) $(CFLAGS) $(LDFLAGS) $(GG_EXE_LDFLAGS)
$(BUILD)/tests/yourfuzz_ggrefract: examples/fuzz_your_refract.c tests/fuzz/replay.c $(STATIC)
	@mkdir -p $(@D)
	$(YOURFUZZ_CC) -o $@ $^ $(IMG_LIBS) $(SYS_LIBS)
$(BUILD)/tests/yourfuzz_textbook: examples/fuzz_your_refract.c tests/fuzz/replay.c \
  examples/textbook_refract.c $(STATIC)
	@mkdir -p $(@D)
	$(YOURFUZZ_CC) -DUSER_REFRACT=textbook_refract -o $@ $^ $(IMG_LIBS) $(SYS_LIBS)

tests: $(TEST_BIN) $(REPLAY_BIN) $(CLI) $(BUILD)/libtextbook_refract.so $(YOURFUZZ)

# Running the suites: each writes TAP to its own file under $(TAP_DIR)
# (tests/run-tests.sh --run), so that make -j runs them side by side; then
# run-tests.sh --report reads the files: the failures by name, a summary.
# TEST_SUITES picks the kinds (check runs fewer in some builds), slowest
# first so that -j starts them early: the CLI suite (tests/cli/run.sh),
# the HTTP suites of ggrt serve (tests/http/, TEST_HTTP of them), the
# cmocka suites (tests/unit/, tests/api/) and the fuzz-corpus replays.
TAP_DIR     = $(BUILD)/tap
RUN_SUITE   = sh tests/run-tests.sh --run
TEST_SUITES ?= cli http unit replay
TEST_HTTP   ?= $(sort $(wildcard tests/http/http_*test.py))
TAP_cli     = $(TAP_DIR)/cli/run.tap
TAP_http    = $(TEST_HTTP:tests/http/%.py=$(TAP_DIR)/http/%.tap)
TAP_unit    = $(TEST_BIN:$(BUILD)/tests/%=$(TAP_DIR)/%.tap)
TAP_replay  = $(REPLAY_BIN:$(BUILD)/tests/%=$(TAP_DIR)/fuzz/%.tap)
TEST_TAPS   = $(foreach k,$(TEST_SUITES),$(TAP_$(k)))

$(TAP_cli): $(CLI) $(REPLAY_BIN) $(YOURFUZZ) $(BUILD)/libtextbook_refract.so FORCE
	@$(CLI_ENV) $(RUN_SUITE) $@ sh tests/cli/run.sh $(CLI)
$(TAP_DIR)/http/%.tap: tests/http/%.py $(CLI) FORCE
	@PYTHONDONTWRITEBYTECODE=1 $(RUN_SUITE) $@ python3 $< $(CLI)
$(TAP_unit): $(TAP_DIR)/%.tap: $(BUILD)/tests/% FORCE
	@CMOCKA_MESSAGE_OUTPUT=TAP $(RUN_SUITE) $@ $<
$(TAP_replay): $(TAP_DIR)/fuzz/replay_%.tap: $(BUILD)/tests/replay_% FORCE
	@$(RUN_SUITE) $@ $< tests/fuzz/corpus/$*

# Run what is built in $(BUILD) (make -j2 test: two suites at a time).
test: $(TEST_TAPS)
	@sh tests/run-tests.sh --report "$(BUILD)" $(TEST_TAPS)

# The check builds' debug information is -g1 (line tables: what a
# sanitizer's or valgrind's stack trace shows) or none; a full -g tree is
# `make` or `make test`, on demand. The release tree keeps CFLAGS' -g: it
# is also the one installcheck installs.
# GG_NO_FORCED_INLINE (lib/core/compiler.h): the compiler's inlining in
# place of always_inline, which made the sanitizer trees' walks many times
# larger: the GCC ASan tree's check went from 1021 to 877 s, run beside
# the old one. Not forced, a static function may take and return a 32-byte
# vector in a file built for SSE (-Wno-psabi: both sides are that file).
SAN_FLAGS = -O1 -g1 -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer \
            -DGG_NO_FORCED_INLINE -Wno-psabi
SAN_LDFLAGS = -fsanitize=address,undefined
# -no-pie: a position-independent ASan ggrt starts by applying 142,000
# relative relocations (the sanitizers' tables of globals and checks),
# about a fifth of its start-up, and the ASan trees start thousands of
# processes. The shared objects keep -fPIC; only the programs' links
# take it (GG_EXE_LDFLAGS).
SAN_EXE_LDFLAGS = -no-pie

# The suites that run the library from several threads at once, run a
# third time under ThreadSanitizer (GCC's; TSan reports make the run fail).
TSAN_TESTS = $(BUILD)/tests/api/test_concurrent $(BUILD)/tests/unit/render/test_render \
             $(BUILD)/tests/unit/load/test_progress $(BUILD)/tests/unit/imageio/test_image
TSAN_CC    ?= gcc
TSAN_FLAGS  = -O1 -g1 -fsanitize=thread -fno-omit-frame-pointer -DGG_NO_FORCED_INLINE -Wno-psabi
test-tsan:
	@TSAN_OPTIONS="halt_on_error=1 $(TSAN_OPTIONS)" $(MAKE) --no-print-directory test TEST_SUITES=unit \
	  TEST_BIN="$(TSAN_TESTS)"

# The second compiler check runs the suites with: the two disagree on what
# C leaves open (an indeterminate value, evaluation order), so code that
# passes with one only is caught (issue 29).
CHECK_CC2 ?= $(if $(GG_CLANG),gcc,clang)
CHECK_DIR2 = $(BUILD)/$(notdir $(firstword $(CHECK_CC2)))

# check: install missing packages, then every check below, CHECK_JOBS at a
# time (default: the processor count; a caller's make -jN is used as
# given): the builds and suites of the trees run side by side, each suite
# into its own TAP file (tests/run-tests.sh). Recursive makes re-read
# pkg-config once the packages are there. Which suites run where:
#  - $(CC) -O3 (release) and $(CC) ASan+UBSan (asan): every suite. ASan
#    is the configuration that matters for the unit, CLI and HTTP suites.
#  - $(CHECK_CC2) -O3 (no -g): the cmocka suites, the corpus replays, the
#    CLI suite (cli/ is C too) and the HTTP routes (tests/http/http_test.py);
#    not every scene over HTTP (the library on each scene: the unit and
#    CLI suites' business) nor the 15 s of slow clients (libmicrohttpd's
#    connection handling, not the compiler's).
#  - $(CHECK_CC2) ASan+UBSan: the cmocka suites and the replays, the C that
#    one compiler may get right and the other wrong; the CLI's memory is
#    the $(CC) ASan run's.
#  - ThreadSanitizer: TSAN_TESTS.
#  - installcheck against the release tree.
#  - the two release trees render every scene file to the same bytes
#    (tests/build/compilers.sh): they have one ggBuildId, so ggrt merge
#    would join their tiles.
CHECK_JOBS ?= $(shell nproc 2>/dev/null || echo 2)
CHECK_J     = $(if $(findstring jobserver,$(MAKEFLAGS)),,-j$(CHECK_JOBS))
# (A recipe line names $(MAKE) itself: only then does make hand the
# sub-make its jobserver; through another variable the sub-make runs -j1.)
CHECK_ARGS  = --no-print-directory GG_WERROR=-Werror
CHECKS      = check-layers check-paths check-asan check-release $(if $(CHECK_CC2),check-cc2-asan check-cc2) \
              check-tsan
check: deps-check
	@$(MAKE) --no-print-directory $(CHECK_J) $(CHECKS)
	@$(if $(CHECK_CC2),sh tests/build/compilers.sh $(BUILD)/release/ggrt $(CHECK_DIR2)/release/ggrt)
	@echo "check: all suites passed (plain and sanitized with $(CC)$(if $(CHECK_CC2), and $(CHECK_CC2)), thread-sanitized, installcheck)"

check-layers:
	@sh tests/build/layers.sh
check-paths:
	@sh tests/build/paths.sh
check-release:
	@$(MAKE) $(CHECK_ARGS) test BUILD=$(BUILD)/release
	@sh tests/build/targets.sh $(BUILD)/release
	@$(MAKE) $(CHECK_ARGS) lib BUILD=$(BUILD)/release
	@sh tests/build/quiet.sh $(BUILD)/release
	@sh tests/build/isa.sh $(BUILD)/release
	@$(MAKE) $(CHECK_ARGS) bench-bin BUILD=$(BUILD)/release
	@sh tests/build/bench.sh $(BUILD)/release
	@$(MAKE) $(CHECK_ARGS) installcheck BUILD=$(BUILD)/release
# The ASan tree's CLI suite samples its scene-by-expression loops (one
# combination in 8, each scene and expression still run) and its tile
# cuts (each path still taken; tests/cli/run.sh, GG_TEST_SAMPLE): an ASan process takes 95-200 ms to the release one's 10
# (most of it page faults on this VM), and the loops start some 4000. The
# clang tree takes one in 4; the release tree runs them all.
check-asan:
	@$(MAKE) $(CHECK_ARGS) test BUILD=$(BUILD)/asan CFLAGS="$(SAN_FLAGS)" LDFLAGS="$(SAN_LDFLAGS)" \
	  GG_EXE_LDFLAGS="$(SAN_EXE_LDFLAGS)" CLI_ENV=GG_TEST_SAMPLE=8
check-cc2:
	@$(MAKE) $(CHECK_ARGS) test BUILD=$(CHECK_DIR2)/release CC="$(CHECK_CC2)" CFLAGS=-O3 \
	  TEST_SUITES="cli http unit replay" TEST_HTTP=tests/http/http_test.py CLI_ENV=GG_TEST_SAMPLE=4
check-cc2-asan:
	@$(MAKE) $(CHECK_ARGS) test BUILD=$(CHECK_DIR2)/asan CC="$(CHECK_CC2)" CFLAGS="$(SAN_FLAGS)" \
	  LDFLAGS="$(SAN_LDFLAGS)" GG_EXE_LDFLAGS="$(SAN_EXE_LDFLAGS)" TEST_SUITES="unit replay"
check-tsan:
	@$(MAKE) $(CHECK_ARGS) test-tsan BUILD=$(BUILD)/tsan CC=$(TSAN_CC) CFLAGS="$(TSAN_FLAGS)" LDFLAGS="-fsanitize=thread"

# scripts/deps.sh GROUP: the packages a target needs (deps = check's).
# check-browser: ggrt serve's page in headless Chromium through Selenium
# (tests/browser/browser_test.py: every scene file, glass.nff in depth, the path filter, the layout;
# 164-171 s on 2 cores in CI runs of 2026-12-05); CI runs it after check. Selenium is
# Debian's python3-selenium, importable by /usr/bin/python3.
BROWSER_PYTHON ?= /usr/bin/python3
check-browser: deps-check deps-browser
	@$(MAKE) --no-print-directory $(BUILD)/release/ggrt BUILD=$(BUILD)/release GG_WERROR=-Werror
	@$(BROWSER_PYTHON) tests/browser/browser_test.py $(BUILD)/release/ggrt --screenshot $(BUILD)/browser/serve.png

# check-cluster: the recipes of examples/cluster/ on a real scheduler
# (tests/cluster/check.sh, docs/cluster.md): as root, munged, slurmctld and
# slurmd on this machine with a key and a slurm.conf in a temporary folder,
# examples/cluster/slurm.sh on gears in 8 tiles of a plan (PLAN=1), then
# parallel.sh locally and over ssh
# to root@127.0.0.1 through a private sshd (config and keys in the folder),
# each merge cmp'd with one process's render; every daemon stopped, the
# folder removed. 30 s on 2 cores. Packages: scripts/deps.sh group cluster.
check-cluster: deps-cluster
	@$(MAKE) --no-print-directory $(BUILD)/release/ggrt BUILD=$(BUILD)/release GG_WERROR=-Werror
	@sh tests/cluster/check.sh $(BUILD)/release/ggrt

# The load benchmark of ggrt serve (prints figures; not a test).
BENCH_CLIENTS ?= 8
BENCH_SECONDS ?= 10
bench-serve: $(CLI)
	python3 bench/http_bench.py $(CLI) --clients $(BENCH_CLIENTS) --seconds $(BENCH_SECONDS)
	python3 bench/http_bench.py $(CLI) --clients $(BENCH_CLIENTS) --seconds $(BENCH_SECONDS) --render

# ggrt plan's cut against equal bands: gears in 8 tiles, each tile a -j 1
# process, the slowest over the fastest tile in wall and CPU seconds
# (bench/plan_bench.sh; prints figures, not a test). About 1 min.
bench-plan: $(CLI)
	@sh bench/plan_bench.sh $(CLI) $(BENCH_PLAN_ARGS)

deps: deps-check
deps-%:
	@sh scripts/deps.sh $*

demo: deps-demo
	@$(MAKE) --no-print-directory all
	$(CLI) render examples/scenes/default.nff -o demo.png
	@echo "demo: wrote demo.png"

# --- install -----------------------------------------------------------

# A folder under PREFIX is written as ${prefix}/..., so that the .pc files
# move with the install (pkg-config --define-prefix, a staged tree).
pc_rel = $(patsubst $(PREFIX)/%,$${prefix}/%,$(1))
$(BUILD)/%.pc: %.pc.in Makefile
	@mkdir -p $(@D)
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(call pc_rel,$(LIBDIR))|' \
	    -e 's|@INCLUDEDIR@|$(call pc_rel,$(INCLUDEDIR))|' -e 's|@VERSION@|$(VERSION)|' $< > $@

# Regenerated every time: PREFIX may differ between calls.
pc:
	@rm -f $(BUILD)/ggrt.pc $(BUILD)/ggrt-core.pc
	@$(MAKE) --no-print-directory $(BUILD)/ggrt.pc $(BUILD)/ggrt-core.pc

# The headers of include/ggrt/, installed and uninstalled by name. The
# shared library is mode 644, as Debian's policy (8.1) and lintian want:
# it is mapped, not executed.
HEADERS := $(sort $(wildcard include/ggrt/*.h))
install: all pc
	$(INSTALL) -d $(DESTDIR)$(INCLUDEDIR)/ggrt $(DESTDIR)$(LIBDIR) $(DESTDIR)$(PKGCONFIGDIR) \
	  $(DESTDIR)$(BINDIR) $(DESTDIR)$(MANDIR)/man1 $(DESTDIR)$(BASHCOMPDIR)
	$(INSTALL) -m 644 include/ggrt.h $(DESTDIR)$(INCLUDEDIR)/
	$(INSTALL) -m 644 $(HEADERS) $(DESTDIR)$(INCLUDEDIR)/ggrt/
	$(INSTALL) -m 644 $(STATIC) $(CORE_STATIC) $(DESTDIR)$(LIBDIR)/
	$(INSTALL) -m 644 $(SHARED) $(DESTDIR)$(LIBDIR)/
	ln -sf libggrt.so.$(VERSION) $(DESTDIR)$(LIBDIR)/$(SONAME)
	ln -sf libggrt.so.$(VERSION) $(DESTDIR)$(LIBDIR)/libggrt.so
	$(INSTALL) -m 644 $(BUILD)/ggrt.pc $(BUILD)/ggrt-core.pc $(DESTDIR)$(PKGCONFIGDIR)/
	$(INSTALL) -m 755 $(CLI) $(DESTDIR)$(BINDIR)/
	$(INSTALL) -m 644 docs/ggrt.1 $(DESTDIR)$(MANDIR)/man1/
	$(INSTALL) -m 644 cli/completion.bash $(DESTDIR)$(BASHCOMPDIR)/ggrt
	@[ -n "$(DESTDIR)" ] || sh scripts/ldcache.sh install "$(LIBDIR)" $(SONAME) "$(LDCONFIG)"

uninstall:
	rm -f $(DESTDIR)$(INCLUDEDIR)/ggrt.h $(DESTDIR)$(LIBDIR)/libggrt.a \
	  $(DESTDIR)$(LIBDIR)/libggrt-core.a $(DESTDIR)$(PKGCONFIGDIR)/ggrt-core.pc \
	  $(DESTDIR)$(LIBDIR)/libggrt.so $(DESTDIR)$(LIBDIR)/$(SONAME) \
	  $(DESTDIR)$(LIBDIR)/libggrt.so.$(VERSION) $(DESTDIR)$(PKGCONFIGDIR)/ggrt.pc \
	  $(DESTDIR)$(BINDIR)/ggrt $(DESTDIR)$(MANDIR)/man1/ggrt.1 $(DESTDIR)$(BASHCOMPDIR)/ggrt
	rm -f $(HEADERS:include/%=$(DESTDIR)$(INCLUDEDIR)/%)
	@[ ! -d $(DESTDIR)$(INCLUDEDIR)/ggrt ] || rmdir $(DESTDIR)$(INCLUDEDIR)/ggrt 2>/dev/null || \
	  echo "uninstall: kept $(DESTDIR)$(INCLUDEDIR)/ggrt: it holds files make install did not put there"
	@[ -n "$(DESTDIR)" ] || sh scripts/ldcache.sh uninstall "$(LIBDIR)" $(SONAME) "$(LDCONFIG)"

# Stage an install under $(BUILD)/stage with PREFIX=/usr and build and run
# every example against it through pkg-config (LD_LIBRARY_PATH pointing into
# the stage); link the core example with -static; then tests/build/install.sh: a
# real install into a temporary prefix, registered with the dynamic linker,
# and README.md's compile lines and its library program run as written,
# without LD_LIBRARY_PATH.
STAGE = $(abspath $(BUILD))/stage
installcheck: $(SHARED) $(BUILD)/libggrt.so
	@nm -D --defined-only $(SHARED) >/dev/null || { echo "installcheck: cannot read $(SHARED)"; exit 1; }
	@bad=$$(nm -D --defined-only $(SHARED) | awk '$$2 != "A" {print $$3}' | grep -v '^gg[A-Z]'); \
	  if [ -n "$$bad" ]; then echo "installcheck: libggrt.so exports internal symbols: $$bad"; exit 1; fi; \
	  echo "installcheck: libggrt.so exports $$(nm -D --defined-only $(SHARED) | awk '$$2 != "A"' | wc -l) symbols, all public gg*"
	@hdr=$$(sed -n 's/^GG_API[^(]*[ *]\(gg[A-Za-z0-9_]*\)(.*/\1/p' include/ggrt.h include/ggrt/*.h | sort); \
	  exp=$$(nm -D --defined-only $(SHARED) | awk '$$2 != "A" {sub(/@.*/, "", $$3); print $$3}' | sort); \
	  if [ "$$hdr" != "$$exp" ]; then echo "installcheck: exports and GG_API declarations differ:"; \
	    echo "$$hdr" > $(BUILD)/api.h.txt; echo "$$exp" > $(BUILD)/api.so.txt; \
	    diff $(BUILD)/api.h.txt $(BUILD)/api.so.txt; exit 1; fi; \
	  echo "installcheck: the exports are the $$(echo "$$hdr" | wc -l) GG_API functions of include/ (tests/api/test_null.c calls each)"
	@bad=$$(objdump -T $(SHARED) | awk '$$3 == "DF" && $$4 != "*UND*" && $$(NF-1) != "GGRT_0" {print $$NF}'); \
	  if [ -n "$$bad" ]; then echo "installcheck: exports outside version GGRT_0 (lib/libggrt.map): $$bad"; exit 1; fi; \
	  echo "installcheck: every export has version GGRT_0 (lib/libggrt.map)"
	@rm -rf $(STAGE)
	@$(MAKE) --no-print-directory install DESTDIR=$(STAGE) PREFIX=/usr >/dev/null
	@got=" $$(PKG_CONFIG_PATH=$(STAGE)/usr/lib/pkgconfig $(PKG_CONFIG) --define-prefix --cflags --libs ggrt-core) "; \
	  for want in -I$(STAGE)/usr/include -L$(STAGE)/usr/lib; do \
	    case "$$got" in *" $$want "*) ;; *) echo "installcheck: ggrt-core.pc does not move with the install:$$got"; exit 1;; esac; \
	  done; \
	  echo "installcheck: the .pc files move with the install (--define-prefix on the stage:$$got)"
	@PKG_CONFIG_SYSROOT_DIR=$(STAGE) PKG_CONFIG_PATH=$(STAGE)/usr/lib/pkgconfig \
	  $(MAKE) --no-print-directory examples EXAMPLE_OUT=$(abspath $(BUILD))/examples
	@for e in $(EXAMPLE_SRC:examples/%.c=%); do \
	  (cd $(abspath $(BUILD))/examples && LD_LIBRARY_PATH=$(STAGE)/usr/lib ./$$e >$$e.log 2>&1) \
	    || { echo "installcheck: example $$e failed:"; cat $(abspath $(BUILD))/examples/$$e.log; exit 1; }; \
	  echo "installcheck: example $$e ran against the staged install"; \
	done
	@PKG_CONFIG_SYSROOT_DIR=$(STAGE) PKG_CONFIG_PATH=$(STAGE)/usr/lib/pkgconfig; \
	  export PKG_CONFIG_SYSROOT_DIR PKG_CONFIG_PATH; out=$(abspath $(BUILD))/examples; \
	  $(CC) -std=c99 -O2 $(CPPFLAGS) -static -o $$out/core_static_static examples/core_static.c \
	    `$(PKG_CONFIG) --static --cflags --libs ggrt-core` \
	    || { echo "installcheck: static link against libggrt-core failed"; exit 1; }; \
	  if readelf -d $$out/core_static_static | grep -q NEEDED; then \
	    echo "installcheck: core_static_static needs shared libraries"; exit 1; fi; \
	  (cd $$out && ./core_static_static $(CURDIR)/examples/scenes/default.nff core_static.ppm 64x48 >/dev/null) \
	    || { echo "installcheck: the static core example failed"; exit 1; }; \
	  echo "installcheck: examples/core_static.c linked with -static against libggrt-core" \
	    "(`$(PKG_CONFIG) --static --libs ggrt-core`) and rendered default.nff"
	@MAKE="$(MAKE)" sh tests/build/install.sh $(BUILD)

# Examples build against an installed libggrt found by pkg-config.
EXAMPLE_OUT ?= $(BUILD)/examples
examples:
	@mkdir -p $(EXAMPLE_OUT)
	@for e in $(EXAMPLE_SRC:examples/%.c=%); do \
	  echo "$(CC) examples/$$e.c \`$(PKG_CONFIG) --cflags --libs ggrt\` -lm"; \
	  $(CC) -std=c99 -Wall -Wextra -pedantic -Werror -O2 $(CPPFLAGS) -o $(EXAMPLE_OUT)/$$e examples/$$e.c \
	    `$(PKG_CONFIG) --cflags --libs ggrt` -lm || exit 1; \
	done

# --- fuzzing and benchmarks ---------------------------------------------

FUZZ_SECONDS ?= 60
FUZZ_CC ?= clang
# FUZZ="obj ply" runs only those harnesses (default: all of tests/fuzz).
FUZZ ?= $(FUZZ_SRC:tests/fuzz/fuzz_%.c=%)
FUZZ_BIN = $(FUZZ:%=$(BUILD)/fuzz/fuzz_%)
FUZZ_SAN = -fsanitize=address,undefined -fno-sanitize-recover=all
# The library is built once with coverage instrumentation (its own tree,
# $(BUILD)/fuzzlib, layer rules as usual); each harness links it (a build
# failure is reported, not fatal); then tests/fuzz/run.sh runs every one for
# FUZZ_SECONDS whatever the others found and ends with a summary; it exits
# 1 if any harness found something.
fuzz: deps-fuzz
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/fuzzlib CC=$(FUZZ_CC) GG_WERROR= \
	  CFLAGS="-g -O1 -fsanitize=fuzzer-no-link $(FUZZ_SAN)" $(BUILD)/fuzzlib/libggrt.a >/dev/null
	@mkdir -p $(BUILD)/fuzz
	@for f in $(FUZZ); do \
	  rm -f $(BUILD)/fuzz/fuzz_$$f; \
	  cli=$$(for p in $(FUZZ_CLI); do case $$p in "$$f":*) echo "$${p#*:}" ;; esac; done); \
	  $(FUZZ_CC) -D_POSIX_C_SOURCE=200809L -Iinclude $(TEST_INC) $(CLI_INC) $(CPPFLAGS) -std=c99 -g -O1 \
	    -fsanitize=fuzzer $(FUZZ_SAN) -o $(BUILD)/fuzz/fuzz_$$f tests/fuzz/fuzz_$$f.c $$cli \
	    $(BUILD)/fuzzlib/libggrt.a $(IMG_LIBS) $(SYS_LIBS) || echo "fuzz: fuzz_$$f did not build"; \
	done
	@sh tests/fuzz/run.sh $(BUILD)/fuzz $(FUZZ_SECONDS) $(FUZZ_BIN)

bench: $(BENCH_BIN)
	@for b in $(BENCH_BIN); do $$b || exit 1; done
# The programs alone (check-release runs them small: tests/build/bench.sh).
bench-bin: $(BENCH_BIN)

# The ray-tree recorder's cost when switched off: the same renders with
# this library and with one built without the recorder, alternated.
bench-trace: $(BUILD)/bench/bench_render
	@$(MAKE) --no-print-directory BUILD=$(BUILD)/norec CFLAGS="$(CFLAGS) -DGG_NO_RECORDER" \
	  $(BUILD)/norec/bench/bench_render >/dev/null
	@sh bench/trace_overhead.sh $(BUILD)/bench/bench_render $(BUILD)/norec/bench/bench_render

# EMBREE=BIN: the embree-whitted anchor's build times beside ggrt's.
bench-mesh: $(BUILD)/bench/bench_mesh
	$< $(if $(EMBREE),--embree $(EMBREE)) $(BENCH_MESH_FLAGS)

bench-optics: $(BUILD)/bench/bench_optics
	$<
	@sh bench/optics_counts.sh $<

bench-%: $(BUILD)/bench/bench_%
	$<

format:
	clang-format -i include/*.h include/ggrt/*.h lib/*/*.c lib/*/*.h cli/*.c cli/*/*.c cli/*/*.h \
	  tests/*/*.c tests/unit/*/*.c tests/common/*.h bench/*.c examples/*.c

# demo.png: what make demo writes into the top folder.
clean:
	rm -rf $(BUILD)
	rm -f demo.png

-include $(wildcard $(BUILD)/lib/*/*.d $(BUILD)/scalar/lib/*/*.d $(BUILD)/cli/*.d $(BUILD)/cli/*/*.d \
  $(BUILD)/tests/*/*.d $(BUILD)/tests/unit/*/*.d)
