"""Stability map: every failure region gives its named error or warning.

The coarse map of :mod:`supercoil.benchmark.stability` runs every solver over its
inputs; the targeted tests drive each method onto the boundary of each failure
region (just inside: a finite, accurate result; just outside: the named error
or warning whose message names the quantity and the limit). Regions already
covered elsewhere (N = 0, S < 0, T' < 0, the low-force zeta bracket, the
denaturation warning, ...) are not repeated here.
"""

import re
import warnings
from typing import ClassVar

import numpy as np
import pytest

import supercoil as sc
from supercoil.benchmark import stability
from supercoil.benchmark.stability import maps_family, maps_rod
from supercoil.core.dna import moroz_nelson as mn
from supercoil.core.dna import plectoneme as pl
from supercoil.core.rod import contact as sco
from supercoil.core.rod import rough as rh
from supercoil.dna.model_parameters import ModelParameter
from supercoil.dna.models import Buckling, DNAModel, HatPoints, unregister_model

u = sc.ureg



@pytest.fixture(scope="module")
def bench_out(background):
    """The output folder of the suite's ``supercoil bench --smoke`` (the background job
    ``bench`` of tests/benchmark/test_bench.py), which computes the whole quick map."""
    proc, out = background.result("bench")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return out


@pytest.fixture(scope="module")
def coarse(bench_out):
    """``stability.run(quick=True)`` of the default materials, as the smoke run computed it
    (pickled there with its attrs: computing it once per session, in the lane)."""
    import pickle

    with open(bench_out / "stability_map.pickle", "rb") as f:
        return pickle.load(f)


#: the tests of the coarse map read it from the smoke run
ON_BENCH = pytest.mark.background("bench")


@pytest.fixture(scope="module")
def rod():
    return sc.load_parameters("silicone_rubber_rod")


# ------------------------------------------------------------------ the coarse map


@ON_BENCH
def test_coarse_map_spans_every_solver_into_its_failure_regions(coarse):
    counts = stability.summary(coarse)
    assert list(counts.columns) == list(stability.CATEGORIES)
    assert set(counts.index) == {
        "smooth_helix", "rough_helix closed_form", "rough_helix ode (k = 0 rad/m)",
        "rough_helix ode (k = 100 rad/m)", "rough_helix ode (k = -100 rad/m)",
        "design_twist_schedule", "twist_spinning", "plectoneme_equilibrium",
        "extension_factor", "hat_curve thermal", "hat_curve athermal",
        *(f"hat_curve {k.removeprefix('family ')}" for k, _, _ in maps_family.cases())}
    # every map reaches a working region and a failure region
    assert (counts["ok"] > 0).all() and (counts["named error"] > 0).all()
    # the outcome is one of the four categories, named errors carry their class
    assert set(coarse["category"]) <= set(stability.CATEGORIES)
    named = coarse[coarse["category"] == "named error"]
    assert named["outcome"].str.fullmatch(r"named error: \w+").all()
    assert (named["detail"].str.len() > 0).all()
    # the table convention: a unit for every column, the axes named per row
    assert set(coarse.attrs["units"]) == set(coarse.columns)
    assert coarse.attrs["units"]["force"] == "pN"
    assert coarse.attrs["units"]["head_tension"] == "N"
    for _, row in coarse.drop_duplicates("solver").iterrows():
        assert np.isfinite(row[row["x_quantity"]]) and np.isfinite(row[row["y_quantity"]])


@ON_BENCH
def test_coarse_map_has_no_wrong_cell(coarse):
    wrong = coarse[coarse["category"] == "WRONG"]
    assert wrong.empty, [(r.solver, r.detail) for r in wrong.itertuples()]


def test_classification_catches_silent_failures():
    """The classifier itself: NaN, unnamed exceptions and numpy warnings are WRONG."""

    def nan_returning():
        return np.float64(np.nan)

    def dividing():
        return np.array([1.0]) / np.array([0.0])

    value, exc, warns = stability.call(dividing)
    assert stability.verdict(exc, warns)[0] == "WRONG"
    value, exc, warns = stability.call(lambda: 1 / 0)
    assert stability.verdict(exc, warns) == (
        "WRONG", "unnamed exception ZeroDivisionError: division by zero")
    value, exc, warns = stability.call(nan_returning)
    assert stability.verdict(exc, warns, stability.finite_problems({"x": value}))[0] == "WRONG"
    value, exc, warns = stability.call(lambda: sc.smooth_helix(
        sc.load_parameters("silicone_rubber_rod"), 0, 0.1 * u.m))
    assert stability.verdict(exc, warns)[0] == "named error: NoHelixError"
    value, exc, warns = stability.call(lambda: sc.extension_factor(
        sc.load_parameters("dna"), 0.4 * u.pN, 0 * u.pN * u.nm, 5 * u.nm))
    assert stability.verdict(exc, warns)[0] == "flagged"


@ON_BENCH
def test_plot_writes_one_png(coarse, bench_out):
    """The smoke run drew the quick map with ``stability.plot`` (``stability_map.png``);
    its process recorded what the figure shows (``stability_plot.json``)."""
    import json

    assert (bench_out / "stability_map.png").stat().st_size > 10_000
    shown = json.loads((bench_out / "stability_plot.json").read_text())
    assert shown["solvers"] == coarse["solver"].nunique()
    panels = [p for p in shown["panels"] if p[0]]
    assert len(panels) == coarse["solver"].nunique()
    assert all(xl and yl for _, xl, yl in panels)
    assert "[pN]" in " ".join(xl for _, xl, _ in panels)


# ------------------------------------------------- alpha -> pi/4: the twist load limit


def _singular_load(rod, cos2a_min=sco.COS2A_MIN):
    """N r / L where [eq ini] (= the smooth helix at S = 0) puts cos 2 alpha at cos2a_min."""
    si = rod.si
    c = cos2a_min
    g = (1 - c) * np.sqrt(1 - c * c) / c
    return g * si.bending_rigidity / (4 * np.pi * si.torsional_rigidity)


SOLVERS_AT_PI_4 = {
    "smooth_helix": lambda rod, n: sc.smooth_helix(rod, n, 0 * u.m),
    "rough closed_form": lambda rod, n: sc.rough_helix(rod, n, method="closed_form",
                                                       n_points=5),
    "rough ode": lambda rod, n: sc.rough_helix(rod, n, method="ode", n_points=5),
    "rough ode k>0": lambda rod, n: sc.rough_helix(rod, n, twist_rate=100 * u.rad / u.m,
                                                   n_points=5),
    "twist_spinning": lambda rod, n: sc.twist_spinning(rod, n, 0 * u.N),
}


@pytest.mark.parametrize("solver", SOLVERS_AT_PI_4)
def test_pi_over_4_boundary_in_the_twist_load(rod, solver):
    """Just below the largest N r / L the result is finite; just above it is a
    SingularityError naming alpha and pi/4 (never an inf tension)."""
    x_star = _singular_load(rod)
    assert x_star == pytest.approx(1.107e8, rel=1e-3)  # seed rod: B/C = E/(2G)
    n_star = x_star * rod.si.length / rod.si.radius
    # far beyond hard contact's validity (Hertz half-width > r from alpha = 0.699 rad):
    # a ValidityWarning, but still a finite number
    with pytest.warns(sc.ValidityWarning, match="Hertz contact half-width"):
        below = SOLVERS_AT_PI_4[solver](rod, 0.98 * n_star)
    alpha = below.alpha0 if solver.startswith("rough") else below.alpha
    assert np.cos(2 * alpha.m_as(u.rad)) > sco.COS2A_MIN
    if solver == "smooth_helix":
        assert np.isfinite(below.tension.m_as(u.N)) and below.tension.m_as(u.N) > 1e6
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.ValidityWarning)
        with pytest.raises(sc.SingularityError, match=r"alpha .*pi/4") as err:
            SOLVERS_AT_PI_4[solver](rod, 1.02 * n_star)
        assert "cos 2 alpha" in str(err.value)
        # mirrored handedness: the same limit
        with pytest.raises(sc.SingularityError, match="pi/4"):
            SOLVERS_AT_PI_4[solver](rod, -1.02 * n_star)


def test_smooth_singularity_message_names_the_twist_load(rod):
    n_star = _singular_load(rod) * rod.si.length / rod.si.radius
    with pytest.raises(sc.SingularityError, match=r"\|N\| r / L up to 1\.1\de\+08"):
        sc.smooth_helix(rod, 1.02 * n_star, [0.0, 0.1] * u.m)


def test_one_bad_element_of_an_array_raises_not_nan(rod):
    L = rod.si.length
    with pytest.raises(sc.NoHelixError, match=r"S = .* >= rod length L"):
        sc.smooth_helix(rod, 40, np.array([0.1, 0.2, L]) * u.m)
    with pytest.raises(sc.NoHelixError, match="N = 0"):
        sc.smooth_helix(rod, [40.0, 0.0], 0.1 * u.m)
    with pytest.raises(sc.NoHelixError, match="N = 0"):
        sc.twist_spinning(rod, [40.0, 0.0], 0.1 * u.N)
    with pytest.raises(sc.SingularityError, match="pi/4"):
        sc.smooth_helix(rod, [40.0, 1e13], 0.1 * u.m)


def test_smooth_helix_just_below_full_slack(rod):
    """S = L (1 - 1e-6) is still a helix satisfying (HC) and Lk = N; S = L is not."""
    L = rod.si.length
    h = sc.smooth_helix(rod, 40, L * (1 - 1e-6) * u.m)
    si = rod.si
    om_hc = sco.twist_density(h.alpha.m_as(u.rad), si.radius, si.bending_rigidity,
                              si.torsional_rigidity)
    assert h.omega.m_as(1 / u.m) == pytest.approx(om_hc, rel=1e-9)
    assert h.linking_number.m == pytest.approx(40, rel=1e-12)
    with pytest.raises(sc.NoHelixError, match="no tail is left"):
        sc.smooth_helix(rod, 40, L * u.m)


# ------------------------------------------------------------- rough helix near s_max


@pytest.mark.parametrize(("method", "k"), [("closed_form", 0.0), ("ode", 0.0), ("ode", -100.0)])
def test_rough_helix_at_one_minus_1e_9_of_s_max(rod, method, k):
    kw = {"method": method} if not k else {"twist_rate": k * u.rad / u.m}
    res = sc.rough_helix(rod, 40, n_points=11, **kw)
    assert res.end == "alpha->0"
    s_max = res.s_max.m_as(u.m)
    s = np.array([0.5, 1 - 1e-9]) * s_max
    p = sc.rough_helix(rod, 40, s=s * u.m, **kw).profile
    assert np.isfinite(p.select_dtypes("number").to_numpy()).all()
    alpha = p["alpha"].to_numpy()
    assert 0 < alpha[1] < 1e-3
    # the slowly-varying-pitch model has failed there, and the strands slip: both said
    assert p["curvature_error_flag"].iloc[1] and not p["curvature_error_flag"].iloc[0]
    assert res.slip_onset is not None and res.slip_onset.m_as(u.m) < s[1]
    # accurate against an independent reference to the map's tolerance
    si = rod.si
    args = (si.radius, si.length, si.bending_rigidity, si.torsional_rigidity)
    y_ref = stability.rough_reference(
        "dop853" if method == "closed_form" else "closed_form" if not k else "lsoda",
        res.alpha0.m_as(u.rad), k, s, *args)
    dyds = np.abs(rh.dy_ds(s, y_ref, np.full_like(s, k), *args))
    bound = stability.ROUGH_TOL_Y + dyds * stability.ROUGH_TOL_S * si.length
    assert np.all(np.abs(2 * np.sin(alpha) ** 2 - y_ref) <= bound)
    with pytest.raises(sc.NoHelixError, match=r"s_max .*pitch is infinite"):
        sc.rough_helix(rod, 40, s=[s_max] * u.m, **kw)


@pytest.mark.parametrize("kw", [{"method": "ode"}, {"twist_rate": -100 * u.rad / u.m}])
def test_rod_without_friction_coefficient_warns_for_the_ode_too(rod, kw):
    with pytest.warns(sc.ValidityWarning, match=r"friction_coefficient is None.*no-slip"):
        res = sc.rough_helix(rod.replace(friction_coefficient=None), 40, n_points=21, **kw)
    assert res.slip_onset is None
    assert res.profile["friction_torque_available"].isna().all()


def test_design_without_friction_coefficient_says_so_and_omits_the_check(rod):
    from supercoil.rod.design import sinusoidal_pitch

    pitch = sinusoidal_pitch(16 * u.mm, 4 * u.mm, 2 * np.pi / (160 * u.mm))
    with pytest.warns(sc.ValidityWarning, match="friction_coefficient is None"):
        t = sc.design_twist_schedule(rod.replace(friction_coefficient=None), pitch,
                                     n_points=101)
    assert "friction_torque_available" not in t and "friction_torque_available" not in \
        t.attrs["units"]
    assert np.isfinite(t.select_dtypes("number").to_numpy()).all()


# ------------------------------------------------- formerly WRONG regions (now fixed)


def test_twist_spinning_beta_at_small_tilt(rod):
    """beta without cancellation at small tilt (was arccos(1/sec beta), 100 % off)."""
    sp = sc.twist_spinning(rod, 1e-4, 1e4 * u.N)
    si = rod.si
    problems = maps_rod.spinning_checks(
        sp.alpha.m_as(u.rad), sp.beta.m_as(u.rad), sp.alpha_slacking.m_as(u.rad), 1e-4, 1e4,
        si.radius, si.length, si.bending_rigidity, si.torsional_rigidity)
    assert not problems, problems


def test_twist_spinning_beta_reference_agrees_where_alpha_is_not_small(rod):
    sp = sc.twist_spinning(rod, 40, [0.0, 0.1, 100.0] * u.N)
    si = rod.si
    for a, b, a0, T in zip(sp.alpha.m_as(u.rad), sp.beta.m_as(u.rad),
                           sp.alpha_slacking.m_as(u.rad), [0.0, 0.1, 100.0], strict=True):
        assert not maps_rod.spinning_checks(a, b, a0, 40, T, si.radius, si.length,
                                              si.bending_rigidity, si.torsional_rigidity)


def _design_error(rod, q, a):
    from supercoil.rod.design import sinusoidal_pitch

    si = rod.si
    r = si.radius
    P0, kw = q * 2 * np.pi * r, 2 * np.pi / (10 * q * 2 * np.pi * r)
    t = sc.design_twist_schedule(rod, sinusoidal_pitch(P0 * u.m, a * P0 * u.m, kw / u.m))
    ref = maps_rod.design_reference(P0, a * P0, kw, t["s"].iloc[-1] * 1e-3, r, si.length,
                                      si.bending_rigidity, si.torsional_rigidity)
    return abs(t["turns"].iloc[-1] - ref) / ref


def test_designed_turns_match_the_linking_number(rod):
    assert _design_error(rod, 20.0, 0.25) < 1e-8  # far from pi/4
    assert _design_error(rod, 16 / (2 * np.pi), 0.25) < 1e-8  # the paper's profile


def test_designed_turns_near_pi_over_4(rod):
    """N(S) from the linking identity stays accurate where k ~ 1/cos^2(2 alpha) grows
    (this profile reaches alpha = 0.75 rad, past hard contact's validity: it warns)."""
    with pytest.warns(sc.ValidityWarning, match="Hertz contact half-width"):
        assert _design_error(rod, 6.3, 0.85) < 1e-6


# --------------------------------------------------------------------------- DNA


def test_largest_plectoneme_force_is_named_with_its_limit(dna):
    with pytest.raises(sc.NoEquilibriumError, match=r"force 200000 pN: above [\d.]+ pN .*r0/2"
                       ) as err:
        sc.plectoneme_equilibrium(dna, 2e5 * u.pN)
    f_max = float(re.search(r"above ([\d.]+) pN", str(err.value)).group(1))
    assert 1e5 < f_max < 1.1e5
    with pytest.warns(sc.ValidityWarning, match="overstretches|hard-core radius"):
        e = sc.plectoneme_equilibrium(dna, 0.999 * f_max * u.pN)
    si = dna.si
    res = pl.hard_core_residuals(0.999 * f_max * 1e-12, e.alpha.m_as(u.rad),
                                   e.radius.m_as(u.m), e.omega.m_as(1 / u.m),
                                   si.bending_rigidity, si.torsional_rigidity, si.kT, si.radius)
    assert max(abs(x) for x in res) < 1e-10
    assert e.radius.m_as(u.m) >= 0.5 * si.radius and e.alpha.m_as(u.rad) < np.pi / 4
    with pytest.raises(sc.NoEquilibriumError, match="pN"):
        sc.plectoneme_equilibrium(dna, 1.001 * f_max * u.pN)


def test_tiny_force_still_has_an_equilibrium(dna):
    e = sc.plectoneme_equilibrium(dna, [1e-4, 1e-3] * u.pN)
    assert np.all(np.isfinite(e.torque.m_as(u.pN * u.nm))) and np.all(e.torque.m > 0)


def test_extension_factor_torque_limit_at_any_force(dna):
    """Q = 0 at M = 2 sqrt(B T - kT^2/32): just below it (Q = 0.01) zeta drops out of
    (0, 1] with a warning, above it a ValidityError naming force and torque; no NaN."""
    si = dna.si
    for f_pn in (1.0, 1e3):
        F = f_pn * 1e-12
        m_c = 2 * np.sqrt(si.bending_rigidity * F - si.kT**2 / 32) * 1e21  # pN nm
        m_in = 2 * np.sqrt(si.bending_rigidity * F - si.kT**2 * (1 / 32 + 0.01)) * 1e21
        with pytest.warns(sc.ValidityWarning, match=r"zeta = -.* outside \(0, 1\]"):
            z = sc.extension_factor(dna, f_pn * u.pN, m_in * u.pN * u.nm, 750 * u.nm)
        assert np.isfinite(z.m)
        with pytest.raises(sc.ValidityError, match=rf"force {f_pn:g} pN, torque [\d.]+ pN nm"):
            sc.extension_factor(dna, f_pn * u.pN, 1.01 * m_c * u.pN * u.nm, 750 * u.nm)
    with pytest.raises(ValueError, match="force must be positive"):
        sc.extension_factor(dna, 0 * u.pN, 1 * u.pN * u.nm, 750 * u.nm)


def test_thermal_hat_fails_named_at_high_force(dna):
    """Above ~43.95 pN the plectoneme torque exceeds what the fluctuating tail can
    carry (zeta's bracket < 0 at M_p): a ValidityError naming force and torque.
    The athermal variant stays defined there."""
    def Q(f_pn):
        si = dna.si
        M = pl.equilibrium(f_pn * 1e-12, si.bending_rigidity, si.torsional_rigidity, si.kT,
                           si.radius).torque
        return float(mn.zeta_bracket(f_pn * 1e-12, M, si.bending_rigidity, si.kT))

    assert Q(43.9) > 0 > Q(44.0)
    with pytest.raises(sc.ValidityError, match=r"force 100 pN, torque [\d.]+ pN nm.*bracket"):
        sc.hat_curve(dna, 100 * u.pN, np.linspace(0, 200, 5))
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        df = sc.hat_curve(dna, 100 * u.pN, np.linspace(0, 200, 5), thermal=False)
    text = " | ".join(str(w.message) for w in rec)
    assert all(issubclass(w.category, sc.ValidityWarning) for w in rec)
    assert "above 65 pN, where B-DNA overstretches" in text
    assert "R = 1.574 nm < r0" in text  # the strands inside the hard core
    assert "above the Euler limit 2 sqrt(B F)" in text  # athermal tail torque > 2 sqrt(B F)
    assert np.isfinite(df["extension"]).all() and (df["extension"] <= 750).all()
    # 29.8-44 pN: the thermal curve is defined, but R < r0 is said (it was silent before)
    with pytest.warns(sc.ValidityWarning, match=r"at 40 pN the superhelix radius R = [\d.]+ nm"):
        sc.hat_curve(dna, 40 * u.pN, np.linspace(0, 200, 5))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc.hat_curve(dna, 29 * u.pN, np.linspace(0, 200, 5))


def test_short_molecule_is_flagged_everywhere(dna):
    """A molecule shorter than 3 bending persistence lengths: every point is flagged
    short_tail, and the unphysical z > L happens only on flagged points."""
    short = dna.replace(length=20 * u.nm)
    with pytest.warns(sc.ValidityWarning, match="outside"):
        df = sc.hat_curve(short, 1 * u.pN, np.linspace(0, 0.5, 11), thermal=True)
    assert df["short_tail"].all()
    df = sc.hat_curve(short, 1 * u.pN, np.linspace(0, 0.5, 11), thermal=False)
    assert df["short_tail"].all()
    # zeta > 1: the formula fails, as flagged, and z > L is never silent
    with pytest.warns(sc.ValidityWarning, match=r"extension 21.2\d* nm .* \[0, L = 20 nm\]"):
        df = sc.hat_curve(short, 1 * u.pN, [0.0], thermal=True)
    assert df["extension"].iloc[0] > 20
    long = sc.hat_curve(dna.replace(length=5 * u.um), 1 * u.pN, np.linspace(0, 40, 41))
    ok = ~long["short_tail"]
    assert ok.all() and long["extension"].between(0, 5000).all()


# ------------------------------------------------------------------ the model family


class _Parabola(DNAModel):
    """A plug-in with one free energy G = L(-F (1 - k (A om)^2) + C om^2 / 2); ``torque_error``
    scales its reported torque away from dG/dN / 2 pi (a model that breaks Maxwell)."""

    name = "stability-parabola"
    summary = "test plug-in for the family map"
    uses_interaction = False
    parameters: ClassVar[dict] = {
        "torque_error": ModelParameter("torque_error", "", 0.0, -1.0, 1.0,
                                       "relative error of the reported torque", "test"),
        "extension_excess": ModelParameter("extension_excess", "", 0.0, 0.0, 1.0,
                                           "relative excess of the stretching term (z above "
                                           "L at small turns, Maxwell kept)", "test"),
    }

    def has_free_energy(self, thermal):
        return True

    def _buckling(self, force, dna, thermal, interaction):
        inf = np.full(np.shape(force), np.inf)
        return Buckling(inf, inf, np.zeros(np.shape(force)))

    def _state(self, turns, force, dna):
        om = 2 * np.pi * np.asarray(turns, float) / dna.length
        a, k = dna.bending_persistence, 0.05
        f = force * (1 + self.values["extension_excess"])
        G = dna.length * (-f * (1 - k * (a * om) ** 2) + 0.5 * dna.torsional_rigidity * om**2)
        z = dna.length * (1 + self.values["extension_excess"]) * (1 - k * (a * om) ** 2)
        M = (2 * f * k * a**2 * om + dna.torsional_rigidity * om)
        return G, np.clip(z, 0, None), M * (1 + self.values["torque_error"])

    def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
        G, z, M = self._state(turns, np.asarray(force, float), dna)
        zeros = np.zeros(np.shape(turns))
        return HatPoints(z, M, zeros, zeros.astype(np.int8), zeros.astype(bool),
                         z / dna.length, G)

    def _free_energy(self, turns, force, dna, thermal, interaction):
        return self._state(turns, np.asarray(force, float), dna)[0]


@pytest.fixture
def parabola_registered():
    sc.register_model(_Parabola, replace=True)
    yield
    unregister_model(_Parabola.name)


def test_family_maps_are_generated_from_the_registry(parabola_registered):
    keys = [k for k, _, _ in maps_family.cases()]
    assert "family stability-parabola" in keys
    assert {"family li-zhao/hard-core", "family li-zhao/screened", "family marko2007"} <= set(keys)
    assert "family stability-parabola" in [k for k, _ in stability.map_builders()]


def test_family_map_catches_a_model_that_breaks_maxwell(parabola_registered):
    dna = sc.load_parameters("dna_150mM_nacl").replace(length=500 * u.nm)
    good = maps_family.family_map(dna, _Parabola(), None, quick=True)[3]
    bad = maps_family.family_map(dna, _Parabola(torque_error=1e-3), None, quick=True)[3]
    outcomes = [o for o, _ in good.ravel()]
    assert "WRONG" not in outcomes and {"ok", "flagged"} & set(outcomes)
    details = [d for o, d in bad.ravel() if o == "WRONG"]
    assert details and all("torque differs from dG/dN / 2 pi" in d for d in details)


def test_family_map_flags_a_warned_extension_outside_0_l_and_calls_an_unwarned_one_wrong(
        parabola_registered, monkeypatch):
    """An extension above L on points not flagged short_tail (Maxwell kept): the shared
    limit warns, so the cell is flagged; with that warning silenced it is WRONG."""
    import supercoil.dna.validity as validity

    dna = sc.load_parameters("dna_150mM_nacl").replace(length=500 * u.nm)
    model = _Parabola(extension_excess=0.01)
    warned = maps_family.family_map(dna, model, None, quick=True)[3]
    pairs = [(o, d) for o, d in warned.ravel() if "outside [0, L" in d]
    assert pairs and all(o == "flagged" for o, _ in pairs)
    monkeypatch.setattr(validity, "extension_messages", lambda *args: [])
    silent = maps_family.family_map(dna, model, None, quick=True)[3]
    wrong = [d for o, d in silent.ravel() if o == "WRONG"]
    assert wrong and all(d.startswith("unflagged extension") for d in wrong)


def test_family_map_classifies_a_slow_cell_as_a_hang(monkeypatch):
    monkeypatch.setattr(maps_family, "HANG_SECONDS", 0.0)
    dna = sc.load_parameters("dna_150mM_nacl")
    out = maps_family.family_map(dna, "marko2007", None, quick=True)[3]
    assert any(o == "WRONG" and d.startswith("hang:") for o, d in out.ravel())
