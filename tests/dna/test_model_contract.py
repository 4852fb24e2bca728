"""The model contract, checked the same way for every registered model and interaction.

Every model in the registry (and a toy registered from outside, as a plug-in would be) goes
through the same checks of the contract in :mod:`supercoil.dna.models.base`:

* the hat curve is even in N (extension, plectoneme length, phase) and odd in N (torque),
  finite, with 0 <= z <= L and phase codes of the shared set;
* buckling: turns and torque positive, slope negative, and the points agree with it
  (stretched below the buckling turns, torque at the buckling turns equal to the
  buckling torque where the model has no jump);
* a model derived from one free energy obeys z = -dG/dF and M = (1/2 pi) dG/dN
  (central differences of the model's own G);
* instances survive pickling and ``replace`` with their own values is the identity;
* unknown names and unregistering are named errors.

The registry is read when the module is collected, so a model added to the package enters
these checks without a new line here.
"""

import pickle
import warnings
from typing import ClassVar

import numpy as np
import pytest

import supercoil as sc
from supercoil.dna.interactions import available_interactions, get_interaction
from supercoil.dna.model_parameters import ModelParameter
from supercoil.dna.models import (
    Buckling,
    DNAModel,
    HatPoints,
    available_models,
    get_model,
    register_model,
    unregister_model,
)
from supercoil.exceptions import ModelError

u = sc.ureg
FORCES = np.array([0.6e-12, 1.5e-12])  # N: above marko2007's 4 kT/A, below denaturation
TURNS = np.linspace(-12.0, 12.0, 49)


class ParabolaRod(DNAModel):
    """A plug-in from outside: a rod that never buckles, G = -F L + (C/2L)(2 pi N)^2 - ..."""

    name = "contract-parabola"
    summary = "test plug-in: straight twisted rod with a linear force-extension"
    uses_interaction = False
    parameters: ClassVar[dict] = {
        "compliance": ModelParameter("compliance", "", 0.1, 0.0, 1.0,
                                     "relative extension lost per unit (2 pi N/L)^2 A", "test"),
    }

    def has_free_energy(self, thermal):
        return True

    def buckling(self, force, dna, thermal, interaction):
        inf = np.full(np.shape(force), np.inf)
        return Buckling(inf, inf, np.full(np.shape(force), -0.0))

    def _g(self, turns, force, dna):
        om = 2 * np.pi * np.asarray(turns, float) / dna.length
        k = self.values["compliance"]
        # G = L (-F (1 - k (A om)^2) + (C kT / 2) om^2): z = L (1 - k (A om)^2), M = dG/dN/2 pi
        a = dna.bending_persistence
        G = dna.length * (-force * (1 - k * (a * om) ** 2)
                          + 0.5 * dna.torsional_rigidity * om**2)
        z = dna.length * (1 - k * (a * om) ** 2)
        M = 2 * force * k * a**2 * om + dna.torsional_rigidity * om
        return G, z, M

    def points(self, turns, force, dna, thermal, interaction, short_tail_length):
        turns = np.asarray(turns, float)
        G, z, M = self._g(turns, np.asarray(force, float), dna)
        zeros = np.zeros(turns.shape)
        return HatPoints(z, M, zeros, zeros.astype(np.int8), zeros.astype(bool),
                         z / dna.length, G)

    def free_energy(self, turns, force, dna, thermal, interaction):
        return self._g(turns, np.asarray(force, float), dna)[0]


@pytest.fixture(scope="module", autouse=True)
def _plugin_registered():
    register_model(ParabolaRod, replace=True)
    yield
    unregister_model(ParabolaRod.name)


def _cases():
    names = [*available_models(), ParabolaRod.name]
    out = []
    for name in dict.fromkeys(names):
        model_cls = ParabolaRod if name == ParabolaRod.name else type(get_model(name))
        inters = available_interactions() if model_cls.uses_interaction else [None]
        out += [pytest.param(name, i, id=f"{name}-{i or 'none'}") for i in inters]
    return out


@pytest.fixture(scope="module")
def molecule():
    """The 150 mM set (the screened interaction needs a salt), SI floats."""
    return sc.load_parameters("dna_150mM_nacl")


def _model_and_interaction(name, inter):
    model = ParabolaRod() if name == ParabolaRod.name else get_model(name)
    return model, (get_interaction(inter) if inter else None)


def _kernel_points(model, inter, dna, turns, force):
    f = np.full(turns.shape, force)
    return model.points(turns, f, dna, True, inter, None)


@pytest.mark.parametrize(("name", "inter"), _cases())
def test_points_are_even_and_odd_in_the_turns_and_bounded(name, inter, molecule):
    model, interaction = _model_and_interaction(name, inter)
    dna = molecule.si
    for F in FORCES:
        p = _kernel_points(model, interaction, dna, TURNS, F)
        q = _kernel_points(model, interaction, dna, -TURNS, F)
        assert isinstance(p, HatPoints)
        for arr in (p.extension, p.torque, p.plectoneme_length):
            assert np.all(np.isfinite(arr)), f"{name}: non-finite points at F = {F}"
        assert np.all(p.extension >= 0) and np.all(p.extension <= dna.length * (1 + 1e-12))
        if not model.symmetric_in_turns:
            continue
        np.testing.assert_allclose(p.extension, q.extension, rtol=1e-12, atol=1e-18)
        np.testing.assert_allclose(p.torque, -q.torque, rtol=1e-12, atol=1e-30)
        np.testing.assert_array_equal(p.phase, q.phase)
        assert set(np.unique(p.phase)) <= {0, 1, 2}


@pytest.mark.parametrize(("name", "inter"), _cases())
def test_buckling_constants_agree_with_the_points(name, inter, molecule):
    model, interaction = _model_and_interaction(name, inter)
    dna = molecule.si
    b = model.buckling(FORCES, dna, True, interaction)
    assert isinstance(b, Buckling)
    assert np.all(b.turns > 0) and np.all(b.torque > 0) and np.all(b.slope <= 0)
    for F, Nb in zip(FORCES, b.turns, strict=True):
        if not np.isfinite(Nb):
            continue
        # well below N_b (a finite-size ensemble rounds the transition: plectonemes already
        # coexist just below the thermodynamic-limit N_b)
        below = _kernel_points(model, interaction, dna, np.array([0.3 * Nb, 0.5 * Nb]), F)
        assert np.all(below.phase == 0), f"{name}: not stretched below N_b at F = {F}"


@pytest.mark.parametrize(("name", "inter"), _cases())
def test_free_energy_derivatives_are_extension_and_torque(name, inter, molecule):
    model, interaction = _model_and_interaction(name, inter)
    if not model.has_free_energy(True):
        with pytest.raises(ModelError, match="free energy"):
            model.free_energy(TURNS, np.full(TURNS.shape, FORCES[0]), molecule.si, True,
                              interaction)
        return
    dna = molecule.si
    # away from phase boundaries (a kink there): points whose phase is that of both neighbours
    N = np.linspace(0.3, 11.7, 24)
    for F in FORCES:
        p = _kernel_points(model, interaction, dna, N, F)
        hN, hF = 1e-4, 1e-4 * F

        def G(n, f):
            return model.free_energy(n, np.full(n.shape, f), dna, True, interaction)

        dG_dN = (G(N + hN, F) - G(N - hN, F)) / (2 * hN)
        dG_dF = (G(N, F + hF) - G(N, F - hF)) / (2 * hF)
        ph = [_kernel_points(model, interaction, dna, N + s, F).phase for s in (-hN, hN)]
        ph += [_kernel_points(model, interaction, dna, N, F + s).phase for s in (-hF, hF)]
        interior = np.all([x == p.phase for x in ph], axis=0)
        assert interior.sum() >= 12
        np.testing.assert_allclose(-dG_dF[interior], p.extension[interior], rtol=1e-5,
                                   atol=1e-4 * dna.length)
        np.testing.assert_allclose(dG_dN[interior] / (2 * np.pi), p.torque[interior],
                                   rtol=1e-5, atol=1e-6 * np.max(np.abs(p.torque)))


@pytest.mark.parametrize(("name", "inter"), _cases())
def test_instances_pickle_and_replace_with_own_values_is_identity(name, inter, molecule):
    model, interaction = _model_and_interaction(name, inter)
    dna = molecule.si
    ref = _kernel_points(model, interaction, dna, TURNS, FORCES[1])
    for m in (pickle.loads(pickle.dumps(model)), model.replace(**model.values)):
        assert repr(m) == repr(model)
        again = _kernel_points(m, interaction, dna, TURNS, FORCES[1])
        np.testing.assert_array_equal(again.extension, ref.extension)
        np.testing.assert_array_equal(again.torque, ref.torque)


@pytest.mark.parametrize(("name", "inter"), _cases())
def test_public_hat_curve_takes_every_registered_model(name, inter, molecule):
    kw = {"interaction": inter} if inter else {}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        df = sc.hat_curve(molecule, [0.6, 1.5] * u.pN, np.linspace(0, 5, 11), model=name, **kw)
    assert len(df) == 22 and df.attrs["units"]["extension"] == "nm"


def test_unknown_and_unregistered_names_are_named_errors():
    with pytest.raises(ModelError, match="unknown model 'no-such'"):
        get_model("no-such")
    with pytest.raises(ModelError, match="no model named 'no-such' is registered"):
        unregister_model("no-such")
    register_model(ParabolaRod, replace=True)
    assert ParabolaRod.name in available_models()
    assert unregister_model(ParabolaRod.name) is ParabolaRod
    assert ParabolaRod.name not in available_models()
    register_model(ParabolaRod)


def test_a_model_that_describes_denaturation_gets_no_denaturation_warning():
    """The shared warning ("the model ignores denaturation") is issued by capability, not
    by model name: a plug-in that declares ``describes_denaturation`` does not get it."""
    class Melting(ParabolaRod):
        name = "contract-melting"
        describes_denaturation = True

    dna = sc.load_parameters("dna_150mM_nacl").replace(length=300 * u.nm)
    with pytest.warns(sc.exceptions.ValidityWarning, match="ignores denaturation"):
        sc.hat_curve(dna, 1.5 * u.pN, [-0.5], model=ParabolaRod())
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc.hat_curve(dna, 1.5 * u.pN, [-0.5], model=Melting())
