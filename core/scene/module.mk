# rad_scene imports scene files through Assimp's C API.
LDLIBS := -lassimp $(LDLIBS)
PKGS   += libassimp-dev
