# radkit: the one build entry.  `make help` lists the targets.
#
#   make            build build/radkit (the program) and build/libradkit.a
#   make test       install missing Debian packages, build, run every test
#   make demo       the main job: the Cornell box (dense, hier, against Monte Carlo), the 1D problem
#   make demo-large what clustering is for: a room of 1000 boxes (a minute; BOXES=, EPS=, TIGHTEN=)
#   make experiments / make bench    the long studies and the benchmark table
#   make fuzz       5000 mutated scenes and options (FUZZ_CASES, FUZZ_SEED); make test runs 200
#   make install    PREFIX=/usr/local DESTDIR=: program, libradkit.so and .a, headers, radkit.pc, radkit.1
#   make examples   stage an install, build examples/*.c against it with pkg-config, run and check them
#   SAN=1 (address+undefined sanitizers), DEBUG=1 (-O0 -g3), WERROR=1 (-Werror)

# ---- settings --------------------------------------------------------------
CC     ?= cc
CXX    ?= c++
SAN    ?= 0
DEBUG  ?= 0
WERROR ?= 0

# BUILD may be set on the command line to keep several trees apart.
ifeq ($(SAN),1)
  BUILD ?= build/san
else ifeq ($(DEBUG),1)
  BUILD ?= build/debug
else
  BUILD ?= build
endif

OPT      := $(if $(filter 1,$(DEBUG)),-O0 -g3,-O2 -g)
# Link-time optimisation of the C code (not the CGAL shim, whose templates
# would make every link slow): the small geometry functions of rad_geom and
# rad_ff inline into hier's and the assembly's loops (5% on a hier solve).
LTO      := $(if $(filter 1,$(DEBUG)),,-flto=auto)
SANITIZE := -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
SANFLAGS := $(if $(filter 1,$(SAN)),$(SANITIZE))
WERRFLAG := $(if $(filter 1,$(WERROR)),-Werror)

# ---- warnings, grouped by language ------------------------------------------
WARN_COMMON := -Wall -Wextra -Wshadow -Wpointer-arith -Wwrite-strings -Wundef \
               -Wcast-align -Wformat=2
WARN_C      := -Wstrict-prototypes -Wmissing-prototypes -Wold-style-definition \
               -Wnested-externs
WARN_CXX    := -Wnon-virtual-dtor

# ---- modules: one folder per module under core/, each with rad_<module>.h ----
# A module may add libraries and Debian packages in its own core/<m>/module.mk.
MODULE_DIRS := $(sort $(dir $(wildcard core/*/rad_*.h)))
# pkg-config and groff-base: make examples links through radkit.pc; the
# manual page test renders radkit.1.
PKGS        := gcc g++ make gnuplot-nox pkg-config groff-base
LDLIBS      := -lm
-include $(wildcard core/*/module.mk)

CPPFLAGS += $(addprefix -I,$(MODULE_DIRS)) -D_POSIX_C_SOURCE=200809L -MMD -MP
CFLAGS   += -std=c11 $(OPT) $(LTO) $(WARN_COMMON) $(WARN_C) $(WERRFLAG) $(SANFLAGS)
CXXFLAGS += -std=c++17 $(OPT) $(WARN_COMMON) $(WARN_CXX) $(WERRFLAG) $(SANFLAGS)
LDFLAGS  += $(SANFLAGS) $(OPT) $(LTO)

LIB_C   := $(filter-out core/cli/%,$(wildcard core/*/*.c))
LIB_CXX := $(wildcard core/*/*.cpp)
CLI_C   := $(wildcard core/cli/*.c)
TEST_C  := $(wildcard tests/*.c)

obj = $(patsubst %,$(BUILD)/obj/%.o,$(basename $(1)))
LIB_OBJ  := $(call obj,$(LIB_C) $(LIB_CXX))
CLI_OBJ  := $(call obj,$(CLI_C))
TEST_OBJ := $(call obj,$(TEST_C))
LINK     := $(if $(LIB_CXX),$(CXX),$(CC))

LIB    := $(BUILD)/libradkit.a
RADKIT := $(BUILD)/radkit
UNIT   := $(BUILD)/tests/unit

# ---- the installable library: a second object tree ---------------------------
# A shared library needs position-independent code, and an installed static
# library must link with any compiler and linker, which GCC's slim LTO objects
# (IR only) do not.  So the libraries `make install` ships are built from
# $(BUILD)/pic/: the same sources with -fPIC, -fno-semantic-interposition
# (nothing is meant to replace radkit's functions at load time, so calls
# within a file inline as in the default build) and, for C,
# -ffat-lto-objects (machine code beside the IR).  The program and the tests
# keep the default objects, so `make` and `make test` cost what they did.
# The shared library exports only the rad_* API (core/libradkit.map).
VERSION  := $(shell sed -n 's/^#define RAD_VERSION "\(.*\)"/\1/p' core/sys/rad_version.h)
SONAME   := libradkit.so.$(firstword $(subst ., ,$(VERSION)))
PUBLIC_H := $(wildcard core/*/rad_*.h)
pic = $(patsubst %,$(BUILD)/pic/%.o,$(basename $(1)))
PIC_OBJ  := $(call pic,$(LIB_C) $(LIB_CXX))
PIC_FLAG := -fPIC -fno-semantic-interposition
PIC_LIB  := $(BUILD)/pic/libradkit.a
SHLIB    := $(BUILD)/pic/libradkit.so.$(VERSION)
MANPAGE  := $(BUILD)/radkit.1

PREFIX     ?= /usr/local
BINDIR     ?= $(PREFIX)/bin
LIBDIR     ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
MANDIR     ?= $(PREFIX)/share/man
INSTALL    ?= install

# ---- targets ---------------------------------------------------------------
.PHONY: all deps test demo demo-large experiments bench fuzz clean echo help install uninstall examples \
        deps-mpi mpi test-mpi
all: $(RADKIT)

deps:
	@sh scripts/deps.sh $(sort $(PKGS))

$(BUILD)/obj/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/%.o: %.cpp | deps
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -c $< -o $@

$(LIB): $(LIB_OBJ)
	@mkdir -p $(dir $@)
	rm -f $@ && gcc-ar rcs $@ $^

$(RADKIT): $(CLI_OBJ) $(LIB)
	$(LINK) $(LDFLAGS) -o $@ $(CLI_OBJ) $(LIB) $(LDLIBS)

$(BUILD)/pic/%.o: %.c | deps
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(PIC_FLAG) -ffat-lto-objects -c $< -o $@

$(BUILD)/pic/%.o: %.cpp | deps
	@mkdir -p $(dir $@)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) $(PIC_FLAG) -c $< -o $@

$(PIC_LIB): $(PIC_OBJ)
	rm -f $@ && gcc-ar rcs $@ $^

# -z defs: every symbol resolved here (the libraries each module.mk names),
# so a program needs only -lradkit.
$(SHLIB): $(PIC_OBJ) core/libradkit.map
	$(LINK) -shared $(LDFLAGS) -Wl,-soname,$(SONAME) -Wl,--version-script=core/libradkit.map \
	  -Wl,-z,defs -o $@ $(PIC_OBJ) $(LDLIBS)

# The manual page is laid out from the program's own --help texts.
$(MANPAGE): $(RADKIT) scripts/manpage.sh
	sh scripts/manpage.sh $(RADKIT) > $@.tmp && mv $@.tmp $@

$(UNIT): $(TEST_OBJ) $(LIB)
	@mkdir -p $(dir $@)
	$(LINK) $(LDFLAGS) -o $@ $(TEST_OBJ) $(LIB) $(LDLIBS)

# The unit binary runs every test, including end-to-end runs of the program.
test: deps $(RADKIT) $(UNIT)
	RADKIT_BIN=$(abspath $(RADKIT)) RADKIT_ROOT=$(CURDIR) $(UNIT)

# The fuzzer is a test of the unit binary (tests/fuzz.c) with more cases.
FUZZ_CASES ?= 5000
FUZZ_SEED  ?= 1
fuzz: deps $(RADKIT) $(UNIT)
	RADKIT_BIN=$(abspath $(RADKIT)) RADKIT_ROOT=$(CURDIR) FUZZ_CASES=$(FUZZ_CASES) FUZZ_SEED=$(FUZZ_SEED) $(UNIT) fuzz_

demo: deps $(RADKIT)
	@sh scripts/demo.sh $(RADKIT)

# What clustering is for: a room of 1000 boxes (a minute; BOXES=, EPS=, TIGHTEN=).
demo-large: deps $(RADKIT)
	@sh scripts/demo_large.sh $(RADKIT)

# The Monte Carlo references first: the other studies measure against them.
experiments: deps $(RADKIT)
	@for run in experiments/reference/run.sh $(filter-out experiments/reference/run.sh,$(wildcard experiments/*/run.sh)); do \
	  echo "== $$run"; RADKIT=$(abspath $(RADKIT)) sh $$run || exit 1; done

bench: deps $(RADKIT)
	@sh scripts/bench.sh $(RADKIT)

# The program is installed as built (static, whole-program optimised); the
# .pc file is written here so that it names this PREFIX.  Libs.private lists
# what the static library needs: the modules' LDLIBS, the C++ runtime (the
# CGAL shim) and the OpenMP runtime (-lgomp, which any compiler can link).
install: $(RADKIT) $(SHLIB) $(PIC_LIB) $(MANPAGE)
	$(INSTALL) -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR)/pkgconfig $(DESTDIR)$(INCLUDEDIR)/radkit \
	  $(DESTDIR)$(MANDIR)/man1
	$(INSTALL) -m 755 $(RADKIT) $(DESTDIR)$(BINDIR)/radkit
	$(INSTALL) -m 755 $(SHLIB) $(DESTDIR)$(LIBDIR)/
	ln -sf $(notdir $(SHLIB)) $(DESTDIR)$(LIBDIR)/$(SONAME)
	ln -sf $(SONAME) $(DESTDIR)$(LIBDIR)/libradkit.so
	$(INSTALL) -m 644 $(PIC_LIB) $(DESTDIR)$(LIBDIR)/libradkit.a
	$(INSTALL) -m 644 $(PUBLIC_H) $(DESTDIR)$(INCLUDEDIR)/radkit/
	$(INSTALL) -m 644 $(MANPAGE) $(DESTDIR)$(MANDIR)/man1/radkit.1
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(patsubst $(PREFIX)/%,$${prefix}/%,$(LIBDIR))|' \
	  -e 's|@INCLUDEDIR@|$(patsubst $(PREFIX)/%,$${prefix}/%,$(INCLUDEDIR))|' \
	  -e 's|@VERSION@|$(VERSION)|' -e 's|@LIBS_PRIVATE@|$(strip $(LDLIBS)) -lstdc++ -lgomp|' \
	  core/radkit.pc.in > $(DESTDIR)$(LIBDIR)/pkgconfig/radkit.pc
	@# A real install (no DESTDIR) into a system directory needs the loader's cache renewed.
	-[ -n "$(DESTDIR)" ] || ldconfig

uninstall:
	rm -f $(DESTDIR)$(BINDIR)/radkit $(DESTDIR)$(LIBDIR)/libradkit.so $(DESTDIR)$(LIBDIR)/$(SONAME) \
	  $(DESTDIR)$(LIBDIR)/$(notdir $(SHLIB)) $(DESTDIR)$(LIBDIR)/libradkit.a \
	  $(DESTDIR)$(LIBDIR)/pkgconfig/radkit.pc $(DESTDIR)$(MANDIR)/man1/radkit.1 \
	  $(DESTDIR)$(INCLUDEDIR)/radkit/rad_*.h
	-rmdir $(DESTDIR)$(INCLUDEDIR)/radkit

# A staged install in $(BUILD)/stage, examples/*.c built against it the way a
# user would (pkg-config; shared, static, and with clang when present), run,
# and their figures checked against the installed program's own.
examples: deps
	rm -rf $(BUILD)/stage
	$(MAKE) --no-print-directory install DESTDIR=$(abspath $(BUILD)/stage) PREFIX=/usr/local
	sh scripts/examples.sh $(abspath $(BUILD)/stage)/usr/local $(abspath $(BUILD)/examples)

# radkit-mpi (issue 18): dense radiosity over MPI ranks with ScaLAPACK, and
# hierarchical runs with their link estimates and gather shared among the
# ranks.  Its own packages, its own target: the plain build and `make test`
# never need MPI.
MPI_PKGS   := openmpi-bin libopenmpi-dev libscalapack-openmpi-dev
RADKIT_MPI := $(BUILD)/radkit-mpi
MPI_SRC    := $(wildcard mpi/*.c)
deps-mpi:
	@sh scripts/deps.sh $(MPI_PKGS)

mpi: deps-mpi $(RADKIT_MPI)

$(RADKIT_MPI): $(MPI_SRC) $(wildcard mpi/*.h) $(LIB) $(filter-out %/radkit.o,$(CLI_OBJ)) | deps-mpi
	mpicc $(CPPFLAGS) -Icore/cli $(CFLAGS) $(MPI_SRC) $(filter-out %/radkit.o,$(CLI_OBJ)) \
	  $(LIB) -lscalapack-openmpi $(LDLIBS) -lstdc++ $(LDFLAGS) -o $@

# 1, 2 and 4 ranks on this machine against the serial program's tables.
test-mpi: mpi $(RADKIT)
	sh scripts/test_mpi.sh $(abspath $(RADKIT)) $(abspath $(RADKIT_MPI))

clean:
	rm -rf build

echo:
	@echo "BUILD    = $(BUILD)"
	@echo "CC       = $(CC)"
	@echo "CXX      = $(CXX)"
	@echo "CPPFLAGS = $(CPPFLAGS)"
	@echo "CFLAGS   = $(CFLAGS)"
	@echo "CXXFLAGS = $(CXXFLAGS)"
	@echo "LDFLAGS  = $(LDFLAGS)"
	@echo "LDLIBS   = $(LDLIBS)"
	@echo "PKGS     = $(sort $(PKGS))"
	@echo "MODULES  = $(MODULE_DIRS)"

help:
	@sed -n '2,12p' Makefile | sed 's/^# \{0,1\}//'

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(TEST_OBJ:.o=.d) $(PIC_OBJ:.o=.d)
