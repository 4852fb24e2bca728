"""An interaction parameter is fitted by name like a DNA field (interaction registered here, for
this module's tests only).

The toy interaction is the paper's hard core with the radius scaled: ``r0 ->
s r0``. In the li-zhao construction r0 enters only through the plectoneme
equilibrium, so fitting ``s`` at fixed r0 = 1.75 nm must give the same
optimum and errors as fitting r0 itself: ``s = r0_fit / 1.75 nm``.
"""

from typing import ClassVar

import numpy as np
import pytest

import supercoil as sc
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting.model import HatCurveModel
from supercoil.dna.interactions import HardCore, get_interaction, unregister_interaction
from supercoil.dna.model_parameters import ModelParameter


class ScaledCore(HardCore):
    name = "scaled-core"
    summary = "test toy: the hard core with its radius scaled by core_scale"
    parameters: ClassVar[dict] = {
        "core_scale": ModelParameter("core_scale", "", 1.0, 0.2, 5.0,
                                     "factor on the hard-core radius", "test choice"),
    }

    def _scaled(self, dna):
        return dna._replace(radius=dna.radius * self.values["core_scale"])

    def _partials(self, alpha, radius, dna):
        return super()._partials(alpha, radius, self._scaled(dna))

    def _equilibrium(self, tension, dna):
        return super()._equilibrium(tension, self._scaled(dna))


@pytest.fixture(autouse=True, scope="module")
def _scaled_core_registered():
    """The toy is registered for this module's tests only: the other tests (the stability
    map's family maps, the model lists) see the built-in registry, as a fresh process does."""
    sc.register_interaction(ScaledCore, replace=True)
    yield
    unregister_interaction("scaled-core")


def test_interaction_parameter_fit_equals_the_radius_fit(data, base, result):
    r = sc.fit_hat_curves(data, base, vary=["twist_persistence", "core_scale"],
                          interaction="scaled-core")
    r0 = base.radius.m_as("nm")
    assert r.parameters["core_scale"].m * r0 == pytest.approx(result.parameters["radius"].m,
                                                              rel=1e-6)
    assert r.stderr["core_scale"].m * r0 == pytest.approx(result.stderr["radius"].m, rel=1e-4)
    assert r.parameters["twist_persistence"].m == pytest.approx(
        result.parameters["twist_persistence"].m, rel=1e-6)
    assert r.interaction.name == "scaled-core"
    assert r.interaction.values["core_scale"] == pytest.approx(r.parameters["core_scale"].m)
    assert "interaction 'scaled-core'" in r.report()
    # fixed by name: the same curve as the molecule with the scaled radius
    fixed = sc.fit_hat_curves(data, base, vary=["twist_persistence"],
                              fixed={"core_scale": 2.0 / r0}, interaction="scaled-core")
    ref = sc.fit_hat_curves(data, base.replace(radius=2.0 * sc.ureg.nm),
                            vary=["twist_persistence"])
    assert fixed.parameters["twist_persistence"].m == pytest.approx(
        ref.parameters["twist_persistence"].m, rel=1e-9)


def test_jacobian_column_of_an_interaction_parameter(data, base):
    spec = fitting.prepare(data, base, vary=["core_scale"], interaction="scaled-core",
                           start={"turns_offset": 0.4})
    prob = HatCurveModel(spec.data, spec.params, spec.dna, spec.model,
                         get_interaction("scaled-core"), spec.thermal)
    u = spec.params.vector() * 1.05
    J = prob.jacobian(u)
    h = 1e-5
    up, um = u.copy(), u.copy()
    up[0] += h
    um[0] -= h
    ref = (prob.residual(up) - prob.residual(um)) / (2 * h)
    np.testing.assert_allclose(J[:, 0], ref, rtol=0, atol=2e-3 * np.abs(ref).max())
