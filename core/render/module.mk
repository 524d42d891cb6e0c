# rad_render: primary rays through rad_vis (Embree), PNG through libpng.
LDLIBS := -lpng $(LDLIBS)
PKGS   += libpng-dev
