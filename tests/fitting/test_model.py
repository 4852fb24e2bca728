"""HatCurveModel: every Jacobian column against central differences, caches, start values,
and the numbers of the fit before the split (identical parameters and errors)."""

import numpy as np
import pytest

import supercoil as sc
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.dna.fitting.covariance import covariance
from supercoil.dna.fitting.model import HatCurveModel, guess_turns_center
from supercoil.dna.interactions import get_interaction

FORCES = np.array([0.3, 0.5, 0.7])


def _problem(base, vary, **kw):
    u = sc.ureg
    df = simulate_rotation_curves(base.replace(length=800 * u.nm), FORCES * u.pN,
                                  points_per_force=30, molecules=["x", "y"],
                                  turns_offset=[0.3, -0.6], extension_offset=[20, -10] * u.nm,
                                  seed=5, **kw)
    spec = fitting.prepare(df, base, vary=vary, start={"turns_offset": 0.1,
                                                       "extension_offset": 5 * u.nm})
    prob = HatCurveModel(spec.data, spec.params, spec.dna, spec.model, spec.interaction,
                         spec.thermal, spec.xi_is_bending)
    return spec, prob


def _central(prob, u, j, h):
    up, um = u.copy(), u.copy()
    up[j] += h
    um[j] -= h
    return (prob.residual(up) - prob.residual(um)) / (2 * h)


@pytest.mark.parametrize("thermal", [True, False])
def test_every_jacobian_column_matches_central_differences(base, thermal):
    vary = ["length", "bending_persistence", "twist_persistence", "radius"]
    spec, prob = _problem(base, vary)
    prob.thermal = thermal
    u = spec.params.vector() * 1.01  # not at a solution
    J = prob.jacobian(u)
    assert J.shape == (spec.data.n, 8)
    assert prob.names == [*vary, "turns_offset[x]", "extension_offset[x]", "turns_offset[y]",
                          "extension_offset[y]"]
    for j, name in enumerate(prob.names):
        ref = _central(prob, u, j, 1e-4 if "turns" in name else 1e-5)
        scale = np.max(np.abs(ref))
        assert scale > 0, name
        np.testing.assert_allclose(J[:, j], ref, rtol=0, atol=2e-3 * scale, err_msg=name)
    # the offsets act on their own molecule only
    mol = spec.data.mol_index
    assert np.all(J[mol == 1, 4] == 0) and np.all(J[mol == 0, 7] == 0)


def test_equilibrium_cache_reuses_the_c_free_state(base):
    """Hard core: alpha, R and the torque do not depend on C; omega = M / C does."""
    si = base.si
    inter = get_interaction("hard-core")
    T = FORCES * 1e-12
    a = inter.equilibrium(T, si)
    C2 = 1.1 * si.torsional_rigidity
    b = inter.equilibrium(T, si._replace(torsional_rigidity=C2, twist_persistence=1.1 *
                                         si.twist_persistence))
    np.testing.assert_allclose(b.torque, a.torque, rtol=1e-12)
    np.testing.assert_allclose(b.radius, a.radius, rtol=1e-12)
    np.testing.assert_allclose(b.omega, a.torque / C2, rtol=1e-12)
    # through the fit's cache: one solve for both molecules' C, same numbers as direct solves
    spec, prob = _problem(base, ["twist_persistence"])
    u = spec.params.vector()
    calls = []
    orig = type(spec.interaction).equilibrium

    def spy(self, tension, dna):
        calls.append(dna.torsional_rigidity)
        return orig(self, tension, dna)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(type(spec.interaction), "equilibrium", spy)
        z1 = prob.extension(u)
        u2 = u.copy()
        u2[0] *= 1.1
        z2 = prob.extension(u2)
    assert len(calls) == 1
    assert not np.allclose(z1, z2)  # C changes the curve (the buckling point)
    # the cached state rescaled to the new C gives the same curve as a fresh solve
    fresh = HatCurveModel(spec.data, spec.params, spec.dna, spec.model, spec.interaction,
                          spec.thermal, spec.xi_is_bending)
    np.testing.assert_allclose(fresh.extension(u2), z2, rtol=1e-13)


def test_points_are_not_recomputed_at_the_same_parameters(base):
    spec, prob = _problem(base, ["radius"])
    u = spec.params.vector()
    prob.residual(u)
    n = prob.n_kernel_calls
    prob.residual(u)
    u_z0 = u.copy()
    u_z0[2] += 1.0  # an extension offset: the kernel does not depend on it
    prob.residual(u_z0)
    assert prob.n_kernel_calls == n
    J = prob.jacobian(u)
    m = prob.n_kernel_calls
    np.testing.assert_array_equal(prob.jacobian(u), J)
    assert prob.n_kernel_calls == m


def test_turns_offset_guess_finds_the_centre_of_symmetry(base):
    u = sc.ureg
    df = simulate_rotation_curves(base, FORCES * u.pN, points_per_force=80, turns_offset=1.3,
                                  noise=2 * u.nm, seed=3)
    d = fitting.RotationData.from_frame(df)
    assert guess_turns_center(d.turns, d.extension, d.force) == pytest.approx(1.3, abs=0.1)
    assert guess_turns_center(d.turns[:4], d.extension[:4], d.force[:4]) == 0.0


def test_thin_svd_covariance_is_the_inverse_normal_matrix():
    rng = np.random.default_rng(1)
    J = rng.normal(size=(500, 4)) * [1, 10, 0.1, 3]
    cov, undetermined, note = covariance(J)
    np.testing.assert_allclose(cov, np.linalg.inv(J.T @ J), rtol=1e-10)
    assert not undetermined.any() and note is None
    J[:, 3] = 2 * J[:, 1]  # the data see only p1 + 2 p3
    cov, undetermined, note = covariance(J, ["a", "b", "c", "d"])
    assert list(undetermined) == [False, True, False, True]
    assert "do not determine b, d" in note and np.isnan(cov[1]).all()


#: Recorded with the fitting code before the split (main d0dad1e, supercoil/dna/fitting/fit.py)
#: on the data below: (value, stderr) in nm / turn.
BEFORE = {
    "single": {"twist_persistence": (95.26128640562253, 0.5564500369488733),
               "radius": (1.9998539733212302, 0.007949857015464554),
               "turns_offset": (0.4011904368334669, 0.00832745972181646),
               "extension_offset": (30.420983171494026, 0.5651926270250447)},
    "two_mol": {"length": (797.734945917669, 2.6169777634622395),
                "bending_persistence": (51.81818891096461, 0.2010328939121571),
                "turns_offset[x]": (0.2968938080974009, 0.009521283670190922),
                "extension_offset[x]": (21.780814030370358, 2.503295643413769),
                "turns_offset[y]": (-0.6100878593748289, 0.009516532921800906),
                "extension_offset[y]": (-7.803102582002266, 2.504680275043234)},
}


def test_fits_give_the_numbers_of_the_code_before_the_split(base, true_dna):
    u = sc.ureg
    single = simulate_rotation_curves(true_dna, FORCES * u.pN, seed=11, noise=5 * u.nm,
                                      turns_offset=0.4, extension_offset=30 * u.nm)
    two = simulate_rotation_curves(base.replace(length=800 * u.nm, bending_persistence=52 * u.nm),
                                   FORCES * u.pN, points_per_force=60, noise=4 * u.nm,
                                   molecules=["x", "y"], turns_offset=[0.3, -0.6],
                                   extension_offset=[20, -10] * u.nm, seed=5)
    for key, df, vary in (("single", single, ["twist_persistence", "radius"]),
                          ("two_mol", two, ["length", "bending_persistence"])):
        # a varied length starts from the data unless given; the old start here
        start = {"length": base.length} if "length" in vary else None
        r = sc.fit_hat_curves(df, base, vary=vary, start=start)
        for name, (v, e) in BEFORE[key].items():
            assert r.parameters[name].m == pytest.approx(v, rel=1e-9), name
            # errors from finite-difference Jacobians: 1e-9 changes of the kernel's
            # rounding (plectoneme blocks) move them by ~1e-9 relative
            assert r.stderr[name].m == pytest.approx(e, rel=1e-7), name


def test_per_force_jacobian_columns_act_on_their_force_only(base):
    u = sc.ureg
    df = simulate_rotation_curves(base, FORCES * u.pN, points_per_force=30, seed=5,
                                  turns_offset=0.2)
    params = sc.fit_parameters(df, base, vary=["twist_persistence", "radius"],
                               start={"turns_offset": 0.1})
    names = params.split_per_force("twist_persistence", FORCES * u.pN)
    spec = fitting.prepare(df, base, params=params)
    prob = HatCurveModel(spec.data, spec.params, spec.dna, spec.model, spec.interaction,
                         spec.thermal)
    uu = spec.params.vector() * 1.02
    J = prob.jacobian(uu)
    for j, name in enumerate(prob.names):
        ref = _central(prob, uu, j, 1e-4 if "turns" in name else 1e-5)
        np.testing.assert_allclose(J[:, j], ref, rtol=0, atol=2e-3 * np.abs(ref).max(),
                                   err_msg=name)
    for j, f in enumerate(FORCES):
        assert prob.names[j] == names[j]
        other = ~np.isclose(spec.data.force, f * 1e-12)
        assert np.all(J[other, j] == 0) and np.any(J[~other, j] != 0)
