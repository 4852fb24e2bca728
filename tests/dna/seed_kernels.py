"""Shared by the float-kernel tests of the free-energy and ensemble models (the ``si``
fixture, the seed set in SI, is in this folder's conftest)."""

from supercoil.core.dna import ensemble as en
from supercoil.core.dna import plectoneme as pl

KT = 4.09e-21
PN, NM, PNNM = 1e-12, 1e-9, 1e-21


def equilibrium_of(si):
    """``T -> PlectonemeState`` of the hard-core plectoneme of ``si`` = (L, B, C, kT, r0)."""
    _, B, C, kT, r0 = si
    return lambda T: pl.equilibrium(T, B, C, kT, r0)


def ensemble_parameters(**kw):
    """Kernel parameters of the ensemble tests (SI): a 1.5 um molecule, A 45 nm, C 100 nm,
    the power-law plectoneme and the linear melted phase, 40 length nodes; ``kw`` override."""
    base = dict(length=1500 * NM, A=45 * NM, C=100 * NM, kT=KT, softening=2.0, P0=13 * NM,
                exponent=0.25, M0=10 * PNNM, nucleation=3 * KT, writhe=1.0,
                melt_energy=1.0 * KT / 0.34e-9, melt_cooperativity=12 * KT, nodes=40)
    base.update(kw)
    return en.EnsembleParameters(**base)
