"""Fixtures of the DNA float-kernel tests."""

import pytest

import supercoil as sc


@pytest.fixture(scope="module")
def si():
    """``(L, B, C, kT, r0)`` of the seed set (SI)."""
    d = sc.load_parameters("dna").si
    return d.length, d.bending_rigidity, d.torsional_rigidity, d.kT, d.radius
