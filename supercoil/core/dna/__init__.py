"""Float-only DNA kernels."""
