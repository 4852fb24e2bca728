"""Uncertainties: singular Jacobians, undetermined parameters, chi-square units."""


import numpy as np
import pytest
from fitting_helpers import NOISE, simulate

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.exceptions import (
    FitWarning,
    ValidityWarning,
)
from supercoil.units import as_turns


def test_singular_jacobian_warns_and_uses_pseudo_inverse(base):
    """Stretched-phase points only: the extension does not depend on r0 there."""
    u = sc.ureg
    # as_turns: buckling_turns may be dimensionless or in turn
    nb = as_turns(sc.buckling_turns(base, 0.5 * u.pN))
    df = simulate_rotation_curves(base, [0.5] * u.pN, turns=np.linspace(-0.6, 0.6, 40) * nb,
                                  noise=2 * u.nm, seed=1)
    with pytest.warns(FitWarning, match="singular.*do not determine radius"):
        r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"],
                              fit_turns_offset=False)
    # the determined parameters keep the pseudo-inverse errors; r0 is not determined
    assert np.isfinite(r.stderr["twist_persistence"].m)
    assert r.stderr["twist_persistence"].m > 0
    assert r.undetermined == ["radius"]
    assert np.isinf(r.stderr["radius"].m)


def test_undetermined_parameter_gets_infinite_stderr(base):
    """One force, stretched phase only (|N| <= 3 at 1 pN), only r0 varied.

    Before the fix the pseudo-inverse gave r0 a standard error of exactly 0 nm.
    """
    u = sc.ureg
    df = simulate_rotation_curves(base, [1.0] * u.pN, turns=np.linspace(-3, 3, 40),
                                  noise=2 * u.nm, seed=1)
    with pytest.warns(ValidityWarning, match="denatures"), \
            pytest.warns(FitWarning, match="do not determine radius; its standard error is inf"):
        r = sc.fit_hat_curves(df, base, vary=["radius"], fit_turns_offset=False)
    assert not np.isfinite(r.stderr["radius"].m)
    assert r.undetermined == ["radius"]
    # the extension offset is determined (the mean extension) and keeps a finite error
    assert 0 < r.stderr["extension_offset"].m < 2
    assert np.isnan(r.covariance.loc["radius"]).all()
    assert np.isnan(r.covariance["radius"]).all()
    assert np.isfinite(r.covariance.loc["extension_offset", "extension_offset"])
    text = r.report()
    radius_row = next(line for line in text.splitlines() if line.strip().startswith("radius"))
    assert "not determined" in radius_row
    assert "not determined" in repr(r)
    frame = r.to_frame()
    assert np.isinf(frame["radius_stderr"].iloc[0]) and not frame["determined"].iloc[0]


def test_chi_square_is_in_the_units_of_the_weighting(result, true_dna, base):
    """The chi-square is dimensionless; with unit weights the noise
    estimate is the sigma (chi_square == nfree), the sum of squares is in nm^2."""
    resid = result.residuals.m_as("nm")
    assert result.sum_squares.m_as("nm**2") == pytest.approx(np.sum(resid**2), rel=1e-9)
    assert result.chi_square == pytest.approx(
        np.sum((resid / result.residual_rms.m_as("nm")) ** 2), rel=1e-9)
    assert result.chi_square == pytest.approx(result.nfree, rel=1e-12)
    assert result.chi_square / result.nfree == pytest.approx(result.reduced_chi_square,
                                                             rel=1e-12)
    assert result.to_frame()["chi_square"].iloc[0] == pytest.approx(result.chi_square)
    assert result.residual_rms.m_as("nm") == pytest.approx(
        np.sqrt(result.sum_squares.m_as("nm**2") / result.nfree), rel=1e-9)
    df = simulate(true_dna, seed=11, sigma_column=True)
    r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"])
    assert r.chi_square == pytest.approx(np.sum((r.residuals.m_as("nm") / NOISE) ** 2),
                                         rel=1e-9)
    assert r.chi_square / r.nfree == pytest.approx(r.reduced_chi_square, rel=1e-12, abs=0)
