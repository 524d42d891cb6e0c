# rad_cluster sorts its nine orders on every thread.
CFLAGS  += -fopenmp
LDFLAGS += -fopenmp
