# radkit: the one build entry.  `make help` lists the targets.
#
#   make            build build/radkit (the program) and build/libradkit.a
#   make test       install missing Debian packages, build, run every test
#   make demo       the main job: the Cornell box (dense, hier, against Monte Carlo), the 1D problem
#   make experiments / make bench    the long studies and the benchmark table
#   make fuzz       5000 mutated scenes and options (FUZZ_CASES, FUZZ_SEED); make test runs 200
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
PKGS        := gcc g++ make gnuplot-nox
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

# ---- targets ---------------------------------------------------------------
.PHONY: all deps test demo experiments bench fuzz clean echo help
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

# The Monte Carlo references first: the other studies measure against them.
experiments: deps $(RADKIT)
	@for run in experiments/reference/run.sh $(filter-out experiments/reference/run.sh,$(wildcard experiments/*/run.sh)); do \
	  echo "== $$run"; RADKIT=$(abspath $(RADKIT)) sh $$run || exit 1; done

bench: deps $(RADKIT)
	@sh scripts/bench.sh $(RADKIT)

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
	@sed -n '2,9p' Makefile | sed 's/^# \{0,1\}//'

-include $(LIB_OBJ:.o=.d) $(CLI_OBJ:.o=.d) $(TEST_OBJ:.o=.d)
