# rad_scene imports scene files through Assimp's C API.
LDLIBS := -lassimp $(LDLIBS)
PKGS   += libassimp-dev
# The corpus test (tests/test_corpus.c) reads the meshes libcgal-demo ships
# (/usr/share/doc/libcgal-dev/data.tar.gz).
PKGS   += libcgal-demo
