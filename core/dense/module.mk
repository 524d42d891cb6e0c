# rad_dense solves with LAPACKE over OpenBLAS.
LDLIBS := -llapacke -lopenblas $(LDLIBS)
PKGS   += liblapacke-dev libopenblas-dev
