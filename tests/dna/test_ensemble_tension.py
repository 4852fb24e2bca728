"""The ensemble's stretched phase at the Moroz-Nelson effective tension (option
``effective_tension``, docs/theory/ensemble.md#211-effective-tension).

References independent of the phase's code path: the present phase (its expansion to
second order in the torque), the package's Moroz-Nelson kernel (its bracket ``Q``,
docs/theory/li-zhao.md#moroz-nelson), finite differences, and the previous kernel's
numbers with the option off.
"""

import numpy as np
import pytest

import supercoil as sc
from supercoil.core.dna import ensemble as en
from supercoil.core.dna import moroz_nelson as mn
from supercoil.core.dna import phases as ph
from supercoil.dna.models.ensemble import Ensemble

KT = 4.09e-21
PN, NM, PNNM = 1e-12, 1e-9, 1e-21
A, C = 45 * NM, 100 * NM


def test_option_off_is_the_previous_model_bit_for_bit():
    """Defaults (option off): the numbers of the kernel before the option existed.

    The two spellings of "off" give the same floats on any machine; the recorded numbers
    (written on one CPU) are met to 1e-13, because numpy's SIMD loops of exp, log and
    power round differently on different CPUs and the torque solves carry that over
    (4e-15 apart on an AVX2-only CPU).
    """
    dna = sc.load_parameters("dna_qian2024_fit").si
    N = np.array([-20.0, 0.0, 8.0, 14.0])
    F = np.array([0.75, 1.0, 0.3, 2.0]) * PN
    default, off = (m.points(N, F, dna, True)
                    for m in (Ensemble(), Ensemble(effective_tension=False)))
    for field in default._fields:
        np.testing.assert_array_equal(getattr(default, field), getattr(off, field),
                                      err_msg=field)
    np.testing.assert_allclose(default.extension, [
        1.4863216227097278e-06, 1.8555692127608533e-06, 1.4116810146893662e-06,
        1.9240924955301197e-06], rtol=1e-13)
    np.testing.assert_allclose(default.torque[[0, 2, 3]], [
        -7.540066083957165e-21, 4.3213545890762564e-21, 1.0861183835236265e-20], rtol=1e-13)
    # at N = 0 the torque is zero but for the torque solve's noise (recorded: 7.3e-26 N m)
    assert abs(default.torque[1]) < 1e-24


@pytest.mark.parametrize("k", [1.0, 2.25])
def test_expansion_to_second_order_in_torque(k):
    """Marko's g: the M^2 term is the present resummed phase's for every k; exact g: it
    is ``(1/C + k (1 - x(F))/(2A)) / kT``: within 1 % of the present one at 0.3 pN, equal
    at high force."""
    F = np.array([0.3, 1.0, 2.0, 50.0]) * PN
    M = 1e-3 * PNNM

    def quad(exact, eff):  # d phi/dM / M at a small torque (the phase is even in M)
        return ph.stretched_gibbs(F, M, A, C, KT, k, exact, True, None, eff).dphi_dM / M

    np.testing.assert_allclose(quad(False, True), quad(False, False), rtol=1e-6)
    _, x = ph.wlc_exact_free_energy_gain(F, A, KT)
    np.testing.assert_allclose(quad(True, True), -(1 / C + k * (1 - x) / (2 * A)) / KT,
                               rtol=1e-6)
    twist = -1 / (KT * C)  # the bending (writhe) parts: (1 - x)/2 against sqrt(kT/(A F))/4
    ratio = (quad(True, True) - twist) / (quad(True, False) - twist)
    # 1.009 / 1.0018 / 1.0009 / 1.00002 at 0.3 / 1 / 2 / 50 pN (A = 45 nm)
    assert np.all(np.diff(ratio) < 0) and 1.005 < ratio[0] < 1.02 and ratio[-1] < 1 + 1e-4
    # the exact second derivative at M = 0 is the same closed form
    d2 = ph.effective_tension_gibbs(F, 0.0, A, C, KT, k).d2phi_dM2
    np.testing.assert_allclose(d2, -(1 / C + k * (1 - x) / (2 * A)) / KT, rtol=1e-12)


def test_marko_g_is_the_moroz_nelson_closed_form():
    """k = 1, Marko's g: ``phi = -F + sqrt(kT F_eff/A) - M^2/(2 kT C)`` and the extension
    ``1 - Q'^(-1/2)/2`` with the package's Moroz-Nelson bracket ``Q' = Q + 1/32``."""
    F = np.array([0.3, 0.5, 1.0, 2.0, 8.0]) * PN
    M = np.array([3.0, -5.0, 8.0, -10.0, 20.0]) * PNNM
    s = ph.effective_tension_gibbs(F, M, A, C, KT, 1.0, exact=False)
    fe = F - M**2 / (4 * KT * A)
    np.testing.assert_allclose(s.phi, -F + np.sqrt(KT * fe / A) - M**2 / (2 * KT * C),
                               rtol=1e-13)
    q = mn.zeta_bracket(F, M, A * KT, KT) + 1.0 / 32.0
    np.testing.assert_allclose(-s.dphi_dF, 1 - 0.5 / np.sqrt(q), rtol=1e-13)


@pytest.mark.parametrize("exact", [True, False])
def test_derivatives_match_finite_differences_on_both_sides_of_the_floor(exact):
    """phi, -x, -Omega, dOmega/dM exact derivatives, above and below ``F_eff = kT/(4A)``."""
    F = np.array([0.3, 1.0, 2.0, 0.3, 0.5]) * PN
    M = np.array([-9.0, 4.0, 12.0, 9.6, -12.5]) * PNNM  # the last two: continuation
    k = 2.5
    fe = ph.effective_tension(F, M, A, KT, k)
    floor = (ph.EFFECTIVE_TENSION_FLOOR if exact else ph.MARKO_TENSION_FLOOR) * KT / A
    assert np.all(fe[3:] < floor) and np.all(fe[3:] > -2 * floor)

    def gibbs(f, m):
        return ph.effective_tension_gibbs(f, m, A, C, KT, k, exact)

    def fd(f, x, h):
        return (8 * (f(x + h) - f(x - h)) - (f(x + 2 * h) - f(x - 2 * h))) / (12 * h)

    g = gibbs(F, M)
    np.testing.assert_allclose(fd(lambda f: gibbs(f, M).phi, F, 1e-6 * F), g.dphi_dF, rtol=1e-6,
                               atol=1e-9)
    np.testing.assert_allclose(fd(lambda m: gibbs(F, m).phi, M, 1e-6 * np.abs(M)), g.dphi_dM,
                               rtol=1e-6)
    np.testing.assert_allclose(fd(lambda m: gibbs(F, m).dphi_dM, M, 1e-6 * np.abs(M)),
                               g.d2phi_dM2, rtol=1e-6)


@pytest.mark.parametrize("exact", [True, False])
def test_no_nan_and_concave_across_the_instability(exact):
    """Over the ensemble's whole torque bracket: finite, concave in M, and continuous with
    its first two M-derivatives where the continuation starts."""
    M = np.linspace(-1.0, 1.0, 4001) * en.TORQUE_BRACKET
    for f in (0.3, 2.0):
        g = ph.effective_tension_gibbs(f * PN, M, A, C, KT, 2.25, exact)
        assert all(np.all(np.isfinite(a)) for a in g)
        assert np.all(g.d2phi_dM2 < 0) and np.all(-g.dphi_dF >= 0)  # concave, x >= 0
    floor = (ph.EFFECTIVE_TENSION_FLOOR if exact else ph.MARKO_TENSION_FLOOR) * KT / A
    Mc = np.sqrt(4 * KT * A * (0.3 * PN - floor) / 2.25)  # F_eff at the floor
    lo, hi = (ph.effective_tension_gibbs(0.3 * PN, Mc * (1 + s), A, C, KT, 2.25, exact)
              for s in (-1e-9, 1e-9))
    for a, b, scale in zip(lo, hi, (1e-12, 1.0, 1e9, 1e27), strict=True):  # J/m, 1, 1/m, ..
        np.testing.assert_allclose(a, b, rtol=1e-6, atol=1e-6 * scale)


def test_ensemble_reports_no_nan_and_names_the_continuation():
    """Low force, many turns of both signs: finite points; a validity message (issued as
    ValidityWarning by hat_curve and the fits) where a reported torque puts the stretched
    phase below the floor, none in a stretched state at 2 pN."""
    dna = sc.load_parameters("dna_qian2024_fit").si
    model = Ensemble(effective_tension=True, twist_bend_softening=4.0)
    N = np.array([-40.0, -12.0, 0.0, 12.0, 40.0])
    F = np.full(N.shape, 0.1 * PN)
    hp = model.points(N, F, dna, True)
    assert np.all(np.isfinite(hp.extension)) and np.all(np.isfinite(hp.torque))
    msgs = model.validity(N, F, hp, dna, True)
    assert any("effective tension" in m and "continuation" in m for m in msgs)
    F2 = np.array([2.0 * PN])
    ok = model.validity(N[2:3], F2, model.points(N[2:3], F2, dna, True), dna, True)
    assert not any("effective tension" in m for m in ok)
    assert Ensemble().validity(N, F, hp, dna, True) == [
        m for m in msgs if "effective tension" not in m]
