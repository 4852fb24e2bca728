"""Calibration nuisance parameter force_spread: the spread of the true force between averaged
molecules (docs/theory/fitting.md#force-spread-of-averaged-curves).

References: off (0) is bit-identical to a fit without it; the 5-node Gauss-Hermite average
equals an independent adaptive quadrature (scipy.integrate.quad_vec) of the model over a
normal force distribution where the integrand is smooth; its Jacobian column matches
central differences; a fit to curves averaged over molecules at known spread forces (41
equal-probability quantiles of the normal, not the Gauss-Hermite nodes) recovers the
spread within its error; a bad value raises a FitError naming it.
"""

import warnings

import numpy as np
import pytest
from fitting_helpers import FORCES
from scipy.integrate import quad_vec
from scipy.stats import norm

import supercoil as sc
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.dna.fitting.model import HatCurveModel
from supercoil.dna.fitting.spread import FORCE_SPREAD_MAX
from supercoil.dna.interactions import get_interaction
from supercoil.dna.models import get_model
from supercoil.exceptions import FitError

TRUE_SPREAD = 0.15
NOISE = 2.0  # nm
TORQUE_NOISE = 0.5  # pN nm


def _problem(df, dna, **kw):
    spec = fitting.prepare(df, dna, **kw)
    return spec, HatCurveModel(spec.data, spec.params, spec.dna, spec.model, spec.interaction,
                               spec.thermal)


@pytest.fixture(scope="module")
def averaged(true_dna):
    """Extension and torque averaged over 41 molecules whose forces are the normal's
    equal-probability quantiles F (1 + s q_j), then noise."""
    u = sc.ureg
    lim = 12.0  # turns: valid at the lowest molecule force (li-zhao, 750 nm)
    turns = np.linspace(-lim, lim, 49)
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, turns=turns,
                                  noise=NOISE * u.nm, seed=4,
                                  torque_noise=TORQUE_NOISE * u.pN * u.nm)
    q = norm.ppf((np.arange(41) + 0.5) / 41)
    model, inter, si = get_model("li-zhao"), get_interaction("hard-core"), true_dna.si
    rng = np.random.default_rng(7)
    for f in FORCES:
        sel = (df["force"] == f).to_numpy()
        n = df.loc[sel, "turns"].to_numpy()
        pts = model.points(np.tile(n, len(q)), np.repeat(f * 1e-12 * (1 + TRUE_SPREAD * q),
                                                         len(n)), si, True, inter, None)
        z = np.asarray(pts.extension).reshape(len(q), -1).mean(axis=0)
        tau = np.asarray(pts.torque).reshape(len(q), -1).mean(axis=0)
        df.loc[sel, "extension"] = (z * 1e9 + rng.normal(0, NOISE, len(n))) / 1e3  # um
        df.loc[sel, "torque"] = tau * 1e21 + rng.normal(0, TORQUE_NOISE, len(n))  # pN nm
    return df


def test_off_is_bit_identical(true_dna, base):
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * sc.ureg.pN, seed=2,
                                  points_per_force=40, torque_noise=1 * sc.ureg.pN * sc.ureg.nm)
    plain = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"])
    off = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"],
                            fixed={"force_spread": 0.0})
    assert "force_spread" not in off.parameters and "force_spread" not in off.fixed
    for name in plain.names:
        assert off.parameters[name].m == plain.parameters[name].m
    assert off.chi_square == plain.chi_square


def test_average_equals_an_adaptive_quadrature(averaged, true_dna):
    s = 0.12
    spec, prob = _problem(averaged, true_dna, vary=["radius"], fixed={"force_spread": s},
                          fit_turns_offset=False, fit_extension_offset=False)
    u = spec.params.vector()
    assert spec.params["force_spread"].value == s
    pts = prob.points(u)[0]
    d = spec.data
    model, inter = get_model("li-zhao"), get_interaction("hard-core")

    def at(xi):
        p = model.points(d.turns, d.force * (1 + s * xi), spec.dna, spec.thermal, inter, None)
        return np.concatenate([p.extension, p.torque]) * norm.pdf(xi), np.asarray(p.phase)

    # where every molecule from xi = -5 to 5 has the same phase the integrand is smooth
    smooth = (at(-5.0)[1] == at(0.0)[1]) & (at(5.0)[1] == at(0.0)[1])
    assert smooth.sum() > 30 and (~smooth).sum() > 10
    ref = quad_vec(lambda x: at(x)[0], -5.0, 5.0, epsabs=1e-30, epsrel=1e-10)[0]
    ref = ref / (norm.cdf(5.0) - norm.cdf(-5.0))
    n = d.n
    z_ref, tau_ref = ref[:n], ref[n:]
    np.testing.assert_allclose(np.asarray(pts.extension)[smooth], z_ref[smooth],
                               rtol=0, atol=0.05e-9)  # 0.05 nm
    np.testing.assert_allclose(np.asarray(pts.torque)[smooth], tau_ref[smooth],
                               rtol=0, atol=0.01e-21)  # 0.01 pN nm
    # and the spread changes the curve by far more than that
    plain = model.points(d.turns, d.force, spec.dna, spec.thermal, inter, None)
    assert np.max(np.abs(np.asarray(plain.extension) - z_ref)[smooth]) > 2e-9


def test_jacobian_column_matches_central_differences(averaged, base):
    spec, prob = _problem(averaged.iloc[::3].reset_index(drop=True), base,
                          vary=["twist_persistence", "force_spread", "torque_scale"],
                          start={"force_spread": 0.12})
    u = spec.params.vector() * 1.01
    J = prob.jacobian(u)
    j = prob.names.index("force_spread")
    h = 1e-5
    up, um = u.copy(), u.copy()
    up[j] += h
    um[j] -= h
    ref = (prob.residual(up) - prob.residual(um)) / (2 * h)
    n = spec.data.n
    assert np.abs(ref[:n]).max() > 0 and np.abs(ref[n:]).max() > 0  # both channels
    np.testing.assert_allclose(J[:, j], ref, rtol=0, atol=3e-3 * np.abs(ref).max())


def test_fit_recovers_the_spread_of_averaged_curves(averaged, true_dna):
    r = sc.fit_hat_curves(averaged, true_dna, vary=["force_spread"])
    s, err = r.parameters["force_spread"].m, r.stderr["force_spread"].m
    assert 0 < err < 0.03
    assert abs(s - TRUE_SPREAD) < 3 * err
    assert "force_spread" in r.report() and "force_spread" in r.to_frame().columns
    # the nominal forces alone (no spread) leave a worse fit and a biased extension offset
    # (true 0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.FitWarning)
        r0 = sc.fit_hat_curves(averaged, true_dna, vary=[])
    assert r0.residual_rms > 1.05 * r.residual_rms
    z0, z0_err = r.parameters["extension_offset"].m, r.stderr["extension_offset"].m
    assert abs(z0) < 3 * z0_err
    assert abs(r0.parameters["extension_offset"].m) > 5 * r0.stderr["extension_offset"].m


@pytest.mark.parametrize("kw", [
    {"fixed": {"force_spread": -0.1}},
    {"fixed": {"force_spread": FORCE_SPREAD_MAX * 1.01}},
    {"vary": ["force_spread"], "start": {"force_spread": 0.5}},
    {"vary": ["force_spread"], "start": {"force_spread": np.nan}},
])
def test_bad_force_spread_names_it(true_dna, kw):
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * sc.ureg.pN, seed=1,
                                  points_per_force=20)
    with pytest.raises(FitError, match=r"force_spread .* outside"):
        sc.fit_hat_curves(df, true_dna, **kw)
