"""Issue 22 items 1-2: the length checked against the data and started from them; the turns
offset started from every channel that locates zero (one-sided data included)."""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.dna.fitting.data import RotationData
from supercoil.dna.fitting.model import guess_turns_center
from supercoil.dna.fitting.start import (
    marko_siggia_relative_extension,
    turns_offset_start,
)
from supercoil.exceptions import FitError, FitWarning

FORCES = np.array([0.3, 0.5, 0.7])  # pN
TRUE_N0 = 0.4


@pytest.fixture(scope="module")
def long_dna(base):
    return base.replace(length=2000 * sc.ureg.nm)


@pytest.fixture(scope="module")
def one_sided(long_dna):
    """The negative side cut at -3 turns, as real data above 0.75 pN (melting)."""
    u = sc.ureg
    df = sc.simulate_rotation_curves(long_dna, FORCES * u.pN, turns=np.linspace(-3, 40, 60),
                                     noise=3 * u.nm, torque_noise=0.3 * u.pN * u.nm,
                                     turns_offset=TRUE_N0, seed=4)
    return df


def test_marko_siggia_inversion():
    kT, P = 4.1e-21, 50e-9
    rel = marko_siggia_relative_extension(np.array([0.1e-12, 1e-12, 10e-12]), P, kT)
    g = rel + 0.25 / (1 - rel) ** 2 - 0.25
    assert g == pytest.approx(np.array([0.1e-12, 1e-12, 10e-12]) * P / kT, rel=1e-9)
    assert np.all(np.diff(rel) > 0)


def test_one_sided_data_start_from_the_torque_zero_not_the_symmetry_centre(one_sided):
    rot = RotationData.from_frame(one_sided)
    old = guess_turns_center(rot.turns, rot.extension, rot.force)
    assert abs(old - TRUE_N0) > 5  # the centre of symmetry of one-sided data: far off
    value, how, found = turns_offset_start(rot.turns, rot.extension, rot.force, rot.torque)
    assert how == "torque zero crossing" and value == pytest.approx(TRUE_N0, abs=0.3)
    assert "hat symmetry" not in found  # the data do not straddle the maximum
    # without torque nothing locates zero: the applied turns' zero, not the symmetry centre
    value, how, _ = turns_offset_start(rot.turns, rot.extension, rot.force)
    assert value == 0.0 and how.startswith("applied turns' zero")


def test_two_sided_data_use_the_hat_symmetry(base):
    u = sc.ureg
    df = sc.simulate_rotation_curves(base, FORCES * u.pN, noise=3 * u.nm, turns_offset=1.3,
                                     seed=2)
    rot = RotationData.from_frame(df)
    value, how, _ = turns_offset_start(rot.turns, rot.extension, rot.force)
    assert how == "hat symmetry" and value == pytest.approx(1.3, abs=0.2)


def test_one_sided_fit_finds_the_offset_and_says_how(one_sided, long_dna):
    # the torque channel is fitted with the extensions; the start is reported
    r = sc.fit_hat_curves(one_sided, long_dna)
    assert r.parameters["turns_offset"].m == pytest.approx(TRUE_N0, abs=0.1)
    assert any("turns_offset starts at" in n and "torque zero crossing" in n for n in r.notes)
    assert "torque zero crossing" in r.report()


def test_fixed_length_below_the_extensions_is_an_error(one_sided, base):
    with pytest.raises(FitError, match=r"reach .* nm .* beyond the contour length L = 750 nm"
                                       r".*dna\.replace\(length=\.\.\.\)"):
        sc.fit_hat_curves(one_sided, base)


def test_varied_length_warns_and_starts_from_the_data(one_sided, base, long_dna):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = sc.fit_hat_curves(one_sided, base,
                              vary=["length", "twist_persistence", "radius"])
    fit = [str(w.message) for w in caught if issubclass(w.category, FitWarning)]
    assert any("beyond the contour length L = 750 nm" in m and "starts the length from the "
               "data" in m for m in fit), fit
    start = r.start["length"].m_as("nm")
    assert start == pytest.approx(2000, rel=0.05)  # worm-like chain at the turns nearest 0
    assert r.parameters["length"].m_as("nm") == pytest.approx(2000, rel=0.01)
    assert any(n.startswith("length starts at") for n in r.notes)
    # a start given by the user wins
    r2 = sc.fit_hat_curves(one_sided, long_dna, vary=["length", "twist_persistence"],
                           start={"length": 1900 * sc.ureg.nm})
    assert r2.start["length"].m_as("nm") == pytest.approx(1900)


def test_length_check_allows_noise_and_a_fitted_offset():
    from supercoil.dna.fitting.start import length_excess

    z = np.full(100, 800e-9)  # 6.7 % above L = 750 nm
    assert length_excess(z, 750e-9, offset_fitted=True) is None  # a bead offset can do it
    assert "800 nm" in length_excess(z, 750e-9, offset_fitted=False)
    assert length_excess(np.full(100, 760e-9), 750e-9) is None  # noise
    assert "1957" in length_excess(np.full(100, 1957e-9), 750e-9, offset_fitted=True)


def _melted_left_side(dna, forces, plateau_from=-4.0):
    """li-zhao curves whose negative side is replaced by a nearly flat plateau beyond
    ``plateau_from`` turns (as melting makes it), which a model symmetric in N cannot fit."""
    u = sc.ureg
    d = sc.simulate_rotation_curves(dna, forces * u.pN, turns=np.linspace(-60, 60, 61),
                                    noise=3 * u.nm, seed=3, model="li-zhao")
    N, z, f = (d[c].to_numpy().copy() for c in ("turns", "extension", "force"))
    for force in np.unique(f):
        s = f == force
        flat = np.interp(plateau_from, N[s], z[s]) + 0.3 * (N[s] - plateau_from)
        z[s] = np.where(N[s] < plateau_from, flat, z[s])
    d["extension"] = z
    return d


def test_a_turns_offset_run_away_from_every_channel_is_named(base):
    """The symmetric model absorbs the asymmetric (melted) side by moving the turns offset
    tens of turns from where the data locate the zero: the fit says so (the offset is
    not bounded, so the fit itself is unchanged), and a clean fit does not warn."""
    data = _melted_left_side(base, np.array([0.5, 1.0, 2.0]))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = sc.fit_hat_curves(data, base)
    n0 = fit.params["turns_offset"].value
    runaway = [str(w.message) for w in caught if issubclass(w.category, FitWarning)
               and str(w.message).startswith("turns_offset = ")]
    assert abs(n0) > 10 and len(runaway) == 1
    assert "from every channel of the data that locates the zero (hat symmetry:" in runaway[0]
    clean = sc.simulate_rotation_curves(base, np.array([0.5, 1.0]) * sc.ureg.pN,
                                        turns=np.linspace(-30, 30, 41), noise=3 * sc.ureg.nm,
                                        turns_offset=TRUE_N0, seed=5)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sc.fit_hat_curves(clean, base)
    assert not [w for w in caught if str(w.message).startswith("turns_offset = ")]
