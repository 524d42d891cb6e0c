# rad_mc traces paths with Embree through rad_vis (vis/module.mk links it) on
# the caller's OpenMP threads.
CFLAGS  += -fopenmp
LDFLAGS += -fopenmp
