# rad_radiosity assembles in parallel with OpenMP.
CFLAGS  += -fopenmp
LDFLAGS += -fopenmp
