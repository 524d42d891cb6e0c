# rad_io: plain C writers; no libraries beyond libc and libm.
