"""The fit's turns-offset column from a model's closed-form slopes (``turn_slopes``).

The free-energy model gives dz/dN and dM/dN at the points the residual already holds
(docs/theory/free-energy.md FE10), so the Jacobian needs no kernel call at N -/+ h. The
references: central differences of the residual (no formula of the slopes reused) and
the same Jacobian with the slopes switched off (the kernel call at N -/+ h, as before).
Where the model has no slope (li-zhao; the torque fitted with fully coiled points; a force
spread) the fit falls back to the kernel call.
"""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting import model as fit_model
from supercoil.dna.fitting import simulate_rotation_curves

FORCES = np.array([0.5, 1.0, 2.0])


def _problem(base, turns_max, torque=False, model="free-energy", interaction="hard-core"):
    u = sc.ureg
    dna = base.replace(length=800 * u.nm)
    extra = {"torque_noise": 0.5 * u.pN * u.nm} if torque else {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        df = simulate_rotation_curves(dna, FORCES * u.pN, turns=np.linspace(
            -turns_max, turns_max, 41) * u.turn, molecules=["x", "y"],
            turns_offset=[0.3, -0.6], extension_offset=[20, -10] * u.nm, seed=5,
            model=model, interaction=interaction, **extra)
    spec = fitting.prepare(df, dna, vary=["twist_persistence"], model=model,
                           interaction=interaction)
    prob = fit_model.HatCurveModel(spec.data, spec.params, spec.dna, spec.model,
                                   spec.interaction, spec.thermal, spec.xi_is_bending)
    return spec, prob


def _turns_columns(prob):
    return [j for j, name in enumerate(prob.names) if name.startswith("turns_offset")]


def _compare(prob, u, monkeypatch):
    """The Jacobian's turns columns, with the slopes, against central differences and
    against the kernel call at N -/+ h."""
    J = prob.jacobian(u)
    with monkeypatch.context() as m:
        m.setattr(fit_model.HatCurveModel, "_model_slopes", lambda self, *a: None)
        prob._jac = None
        J_fd = prob.jacobian(u)
    for j in _turns_columns(prob):
        up, um = u.copy(), u.copy()
        up[j] += 1e-4
        um[j] -= 1e-4
        ref = (prob.residual(up) - prob.residual(um)) / 2e-4
        scale = np.max(np.abs(ref))
        assert scale > 0
        # points within 1e-4 turn of a phase change are off in the differences: none here
        np.testing.assert_allclose(J[:, j], ref, rtol=0, atol=1e-6 * scale)
        np.testing.assert_allclose(J[:, j], J_fd[:, j], rtol=0, atol=1e-6 * scale)
    return J, J_fd


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("torque", [False, True])
def test_turns_columns_from_the_slopes_match_central_differences(base, torque, monkeypatch):
    spec, prob = _problem(base, 20.0, torque)
    u = spec.params.vector() * 1.01
    assert prob._model_slopes(u, *_n_eff(prob, u)) is not None  # the slopes are used
    calls = prob.n_kernel_calls  # the points at u are cached now
    prob.jacobian(u)
    assert prob.n_kernel_calls - calls == 1  # the twist persistence's column only
    _compare(prob, u, monkeypatch)


def _n_eff(prob, u):
    n0 = prob.unpack(u)[3]
    return prob.data.turns - n0[prob.data.mol_index], prob.scale("torque_scale", u)


@pytest.mark.filterwarnings("ignore")
def test_fully_coiled_points_with_the_torque_fall_back_to_the_kernel(base, monkeypatch):
    """+-60 turns on 800 nm: fully coiled points, whose dM/dN the slopes do not have."""
    spec, prob = _problem(base, 60.0, torque=True)
    u = spec.params.vector()
    pts = prob.points(u)[0]
    assert np.any(pts.phase == 2)
    assert prob._model_slopes(u, *_n_eff(prob, u)) is None
    _compare(prob, u, monkeypatch)
    # without the torque channel the slopes cover them (z = 0 there)
    spec, prob = _problem(base, 60.0, torque=False)
    assert prob._model_slopes(spec.params.vector(), *_n_eff(prob, spec.params.vector())) \
        is not None
    _compare(prob, spec.params.vector(), monkeypatch)


@pytest.mark.filterwarnings("ignore")
def test_a_model_without_slopes_uses_the_kernel(base):
    spec, prob = _problem(base, 20.0, model="li-zhao")
    u = spec.params.vector()
    assert prob._model_slopes(u, *_n_eff(prob, u)) is None


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize("interaction", ["hard-core", "screened"])
def test_the_fit_is_the_same_with_fewer_kernel_calls(base, interaction, monkeypatch):
    """The fitted values within 1e-7 and their errors within 1e-5 of the fit that
    differentiates in the turns by kernel calls; one kernel call fewer per Jacobian."""
    u = sc.ureg
    dna = base.replace(length=800 * u.nm)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = simulate_rotation_curves(dna, FORCES * u.pN, points_per_force=40,
                                        noise=5 * u.nm, seed=2)
    if interaction == "screened":
        dna = dna.replace(salt=150 * u.mM)
    kw = {"vary": ["twist_persistence"], "model": "free-energy", "interaction": interaction}
    got = sc.fit_hat_curves(data, dna, **kw)
    with monkeypatch.context() as m:
        m.setattr(fit_model.HatCurveModel, "_model_slopes", lambda self, *a: None)
        ref = sc.fit_hat_curves(data, dna, **kw)
    assert got.names == ref.names and got.stderr.keys() == ref.stderr.keys()
    np.testing.assert_allclose(got.x, ref.x, rtol=1e-7)
    for name, e in ref.stderr.items():
        np.testing.assert_allclose(got.stderr[name].magnitude, e.magnitude, rtol=1e-5,
                                   err_msg=name)
    assert got.nfev == ref.nfev
