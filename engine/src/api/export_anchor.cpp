// The shared library has no code of its own: it is rdv_core linked whole, with only rdv_* exported.
