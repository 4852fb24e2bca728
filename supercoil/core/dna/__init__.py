"""Float-only kernels of the DNA scenes (plectoneme, interactions, hat-curve models)."""
