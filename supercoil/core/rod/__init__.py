"""Float-only kernels of the rod scenes (contact, smooth, rough, designed, twist-spinning)."""
