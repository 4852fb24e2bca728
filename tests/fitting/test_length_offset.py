"""Length and extension offset both free: the degenerate valley z = L g(F) + z0 is named.

On the published curves of real DNA the fit with both free ran the length to 1e7 nm
along a valley where only ``L g(F) + z0`` is fixed; the fit must say so and name the fix.
"""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.exceptions import FitWarning

LENGTH_NM = 2190.0


@pytest.fixture(scope="module")
def dna():
    return sc.load_parameters("dna").replace(length=LENGTH_NM * sc.ureg.nm)


def _fit(data, dna, vary, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fit = sc.fit_hat_curves(data, dna, vary=vary, **kw)
    return fit, [str(w.message) for w in caught if issubclass(w.category, FitWarning)]


def test_length_and_offset_on_one_force_are_named_degenerate_with_the_fix(dna):
    u = sc.ureg
    data = sc.simulate_rotation_curves(dna, [2.0] * u.pN, turns=np.linspace(0, 25, 50),
                                       noise=5 * u.nm, seed=1)
    fit, msgs = _fit(data, dna, ["length", "twist_persistence"])
    r = fit.correlation.loc["length", "extension_offset"]
    assert abs(r) > 0.99  # one force: the extension fixes only L g(F) + z0
    named = [m for m in msgs if m.startswith("length and extension_offset are degenerate")]
    assert len(named) == 1, msgs
    assert f"correlation {r:+.4f}" in named[0]
    assert "fit_extension_offset=False" in named[0] and "dna.replace(length=" in named[0]
    # the fix: the offset held at 0 (the simulated data have none) determines the length
    fixed, msgs = _fit(data, dna, ["length", "twist_persistence"], fit_extension_offset=False)
    assert not [m for m in msgs if "are degenerate" in m]
    err = fixed.stderr["length"].m_as("nm")
    assert err < 0.05 * fit.stderr["length"].m_as("nm")
    assert abs(fixed.parameters["length"].m_as("nm") - LENGTH_NM) < 5 * err


def test_a_determined_length_correlated_with_its_offset_is_not_reported(dna):
    """Three forces: the correlation is high (-0.99) but the length is fixed to 0.2 %."""
    u = sc.ureg
    data = sc.simulate_rotation_curves(dna, [0.3, 0.5, 0.7] * u.pN, points_per_force=40,
                                       noise=5 * u.nm, seed=1)
    fit, msgs = _fit(data, dna, ["length"])
    assert abs(fit.correlation.loc["length", "extension_offset"]) > 0.98
    assert fit.stderr["length"].m_as("nm") < 0.01 * LENGTH_NM
    assert not [m for m in msgs if "are degenerate" in m], msgs


def test_a_length_run_away_in_a_fit_that_did_not_converge_names_the_fix(dna):
    """On the published curves the fit stopped at max_nfev with L = 4e5 nm and said only
    "did not converge": the message now names the valley and the fix."""
    from supercoil.dna.fitting.diagnostics import runaway_hint

    u = sc.ureg
    data = sc.simulate_rotation_curves(dna, [1.0, 2.0] * u.pN, points_per_force=20, seed=1)
    params = sc.fit_parameters(data, dna, vary=["length", "twist_persistence"])
    start = params.vector()
    j = params.free.index("length")
    ran = start.copy()
    ran[j] *= 190  # 2190 nm -> 4.2e5 nm
    hint = runaway_hint(params, ran)
    assert "the length ran from its start 2190 nm to 416100 nm" in hint
    assert "fit_extension_offset=False" in hint and "dna.replace(length=" in hint
    assert runaway_hint(params, start * 1.5) == ""  # moved, not ran away
    held = sc.fit_parameters(data, dna, vary=["length", "twist_persistence"],
                             fit_extension_offset=False)
    assert runaway_hint(held, ran) == ""  # no offset to trade with
