# rad_vis: visibility over Embree 3.  OpenMP for the callers' parallel loops.
LDLIBS  := -lembree3 $(LDLIBS)
PKGS    += libembree-dev
CFLAGS  += -fopenmp
LDFLAGS += -fopenmp
