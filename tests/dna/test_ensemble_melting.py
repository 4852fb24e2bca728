"""The ensemble's melted phase beyond the linear one (docs/theory/melting.md).

References independent of the kernel's code path: finite differences of the phases'
Gibbs free energies and of the ensemble's G(N, F); the Langevin function written out
(the freely jointed chain); the linear melted phase of ``phases.py`` (the term off).
"""

import numpy as np
import pytest
from seed_kernels import KT, NM, PN, PNNM, ensemble_parameters

import supercoil
from supercoil.core.dna import ensemble as en
from supercoil.core.dna import melting as ml
from supercoil.core.dna import phases as ph
from supercoil.exceptions import ValidityError

TWO_PI = 2 * np.pi


def _par(**kw):
    """The melting tests' set: the linear melted phase at x_m = 0.07, 30 nodes, loop off."""
    return ensemble_parameters(**{"melt_extension": 0.07, "nodes": 30, "physical_loop": False,
                                  **kw})


def _fd(f, x, h):
    """Fourth-order central difference."""
    return (8 * (f(x + h) - f(x - h)) - (f(x + 2 * h) - f(x - 2 * h))) / (12 * h)


VARIANTS = {"ss": dict(melt_ss_elastic=True), "compliant": dict(melt_twist_stiffness=30 * NM),
            "ss-compliant": dict(melt_ss_elastic=True, melt_twist_stiffness=30 * NM),
            "all": dict(melt_ss_elastic=True, melt_twist_stiffness=30 * NM,
                        plectoneme_melting=True)}


def test_defaults_are_the_linear_melted_phase_bit_identically():
    F = np.array([0.3, 1.0, 2.0]) * PN
    M = np.array([-9.0, -11.0, 4.0]) * PNNM
    par = _par()
    a = ml.tail_melted_gibbs(F, M, par)
    b = ph.simple_melted_gibbs(F, M, par.melt_energy, par.melt_extension, par.melt_twist)
    for u, v in zip(a, b, strict=True):
        assert np.array_equal(u, v)


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_melted_phase_derivatives_match_finite_differences(variant):
    F = np.array([0.3, 1.0, 2.0]) * PN
    M = np.array([-9.0, -11.0, 4.0]) * PNNM
    par = _par(**VARIANTS[variant])

    def gibbs(f, m):
        return ml.tail_melted_gibbs(f, m, par)

    g = gibbs(F, M)
    np.testing.assert_allclose(_fd(lambda f: gibbs(f, M).phi, F, 1e-5 * F), g.dphi_dF,
                               rtol=1e-6)
    np.testing.assert_allclose(_fd(lambda m: gibbs(F, m).phi, M, 1e-6 * np.abs(M)),
                               g.dphi_dM, rtol=1e-6)
    np.testing.assert_allclose(_fd(lambda m: gibbs(F, m).dphi_dM, M, 1e-6 * np.abs(M)),
                               g.d2phi_dM2, rtol=1e-6)


def test_single_strand_extension_is_the_freely_jointed_chain():
    # two strands share the force; each is a freely jointed chain of Kuhn length b with an
    # additive stretch term: x_m = (l/r) (coth u - 1/u + f/S), u = f b / kT, f = F/2
    F = np.array([0.3, 1.0, 2.0]) * PN
    par = _par(melt_ss_elastic=True)
    d = ml.DEFAULTS
    f = F / 2
    u = f * d["ss_kuhn_length"] / KT
    ref = d["ss_contour_per_base"] / d["rise_per_bp"] * (
        1 / np.tanh(u) - 1 / u + f / d["ss_stretch_modulus"])
    x = -ml.tail_melted_gibbs(F, -10 * PNNM, par).dphi_dF
    np.testing.assert_allclose(x, ref, rtol=1e-12)
    assert np.all(np.diff(x) > 0)  # the bubble lengthens with force


def test_bubbles_in_the_plectoneme():
    """Off: the plectoneme phase bit-identically; on: a proper phase that melts."""
    F = np.array([0.5, 1.0, 2.0]) * PN
    M = np.array([-9.0, -11.0, 6.0]) * PNNM
    off, on = _par(), _par(plectoneme_melting=True)
    a = en.plectoneme_phase(F, M, off)
    b = ph.plectoneme_gibbs(F, M, off.P0, off.exponent, off.M0, KT)
    assert all(np.array_equal(u, v) for u, v in zip(a, b, strict=True))

    def gibbs(f, m):
        return en.plectoneme_phase(f, m, on)

    g = gibbs(F, M)
    assert np.all(g.dphi_dF == 0.0)  # no extension in the plectoneme, melted or not
    np.testing.assert_allclose(_fd(lambda m: gibbs(F, m).phi, M, 1e-6 * np.abs(M)),
                               g.dphi_dM, rtol=1e-6)
    np.testing.assert_allclose(_fd(lambda m: gibbs(F, m).dphi_dM, M, 1e-6 * np.abs(M)),
                               g.d2phi_dM2, rtol=1e-6)
    # melting in the plectoneme: far below the melting torque its twist density is that of
    # melted DNA (Omega_m), above it that of the B-DNA plectoneme
    deep = gibbs(np.array([1 * PN]), np.array([-40 * PNNM]))
    assert -deep.dphi_dM[0] == pytest.approx(on.melt_twist, rel=1e-3)
    assert g.phi[2] == pytest.approx(b.phi[2], rel=1e-3, abs=0)  # positive torque: no bubbles


def test_non_positive_melted_twist_stiffness_is_named():
    with pytest.raises(ValidityError, match="melt_twist_stiffness"):
        ml.tail_melted_gibbs(1 * PN, -10 * PNNM, _par(melt_twist_stiffness=-1 * NM))


@pytest.mark.parametrize("effective_tension", [False, True])
@pytest.mark.parametrize("case", [(-20.0, 2.0), (-24.0, 0.75)])
def test_ensemble_maxwell_with_the_melted_phase(case, effective_tension):
    """<M> = dG/dN / 2 pi and <z> = -dG/dF (so Maxwell holds) with every new term on, the
    stretched phase as shipped or at the effective tension."""
    N0, F0 = case
    par = _par(nodes=12, effective_tension=effective_tension, **VARIANTS["all"])
    hN, hF = 1e-3, 1e-4 * F0 * PN
    k = np.array([1, -1, 2, -2])
    # one vectorised call: the point, four steps in N, four in F
    N = np.concatenate([[N0], N0 + k * hN, np.full(4, N0)])
    F = np.concatenate([[F0 * PN], np.full(4, F0 * PN), F0 * PN + k * hF])
    p = en.points(N, F, par)
    G = p.free_energy

    def fd(g, h):
        return (8 * (g[0] - g[1]) - (g[2] - g[3])) / (12 * h)

    assert p.torque[0] == pytest.approx(fd(G[1:5], hN) / TWO_PI, rel=1e-6, abs=0)
    assert p.extension[0] == pytest.approx(-fd(G[5:9], hF), rel=1e-6)
    assert p.torque[0] < -5 * PNNM  # on the negative plateau (bubbles in tail or plectoneme)


def test_model_options_reach_the_melted_phase():
    """``ss_melted``/``plectoneme_melting`` change the melting side only."""
    from supercoil.dna.models.ensemble import Ensemble

    u = supercoil.ureg
    dna = supercoil.DNA(length=1500 * u.nm, bending_persistence=45 * u.nm,
                        twist_persistence=100 * u.nm, radius=1 * u.nm,
                        temperature=296 * u.K).si
    off = Ensemble(ss_melted=False, plectoneme_melting=False, melted_extension=0.07)
    on = Ensemble(ss_melted=True, plectoneme_melting=True)
    par = on.kernel_parameters(dna)
    assert par.melt_ss_elastic and par.plectoneme_melting
    assert not off.kernel_parameters(dna).melt_ss_elastic
    # the tail at 2 pN: identical at positive torque (no bubbles there, to 1e-6), longer
    # beyond the melting torque (two stretched single strands are longer than x_m = 0.07)
    F, M = np.full(2, 2 * PN), np.array([8.0, -12.0]) * PNNM
    a = en.tail_gibbs(F, M, off.kernel_parameters(dna))[0]
    b = en.tail_gibbs(F, M, par)[0]
    assert b.dphi_dF[0] == pytest.approx(a.dphi_dF[0], rel=1e-6)
    assert -b.dphi_dF[1] > -a.dphi_dF[1] + 0.01
