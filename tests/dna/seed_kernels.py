"""Shared by the float-kernel tests of the free-energy model (the ``si`` fixture, the seed
set in SI, is in this folder's conftest)."""

from supercoil.core.dna import plectoneme as pl


def equilibrium_of(si):
    """``T -> PlectonemeState`` of the hard-core plectoneme of ``si`` = (L, B, C, kT, r0)."""
    _, B, C, kT, r0 = si
    return lambda T: pl.equilibrium(T, B, C, kT, r0)
