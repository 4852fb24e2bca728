"""Benchmarks: work-precision diagrams, the stability map, the unit-boundary cost.

Run them with ``supercoil bench --out DIR``. Nothing here is imported by the
physics modules, and no timing is ever asserted in the test suite.
"""
