# rad_mesh is the CGAL shim (header-only CGAL 5 with GMP/MPFR for exact predicates).
# It is C++, so the program links with $(CXX) and needs the C++ runtime.
LDLIBS := -lgmp -lmpfr $(LDLIBS)
PKGS   += libcgal-dev libgmp-dev libmpfr-dev
# The contact cut examines its candidate pairs on every thread.
CXXFLAGS += -fopenmp
