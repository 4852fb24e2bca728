"""Float-only numerical kernels of supercoil.

Everything under ``supercoil.core`` works on plain floats and numpy arrays in
SI units (m, N, J, N m, N m^2, rad, K) and never imports pint (enforced by
``tests/test_architecture.py``). The unit-checking public API wraps these
kernels; call the kernels directly inside tight loops when the inputs are
already SI floats.
"""
