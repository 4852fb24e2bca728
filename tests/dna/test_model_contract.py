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

    def _buckling(self, force, dna, thermal, interaction):
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

    def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
        turns = np.asarray(turns, float)
        G, z, M = self._g(turns, np.asarray(force, float), dna)
        zeros = np.zeros(turns.shape)
        return HatPoints(z, M, zeros, zeros.astype(np.int8), zeros.astype(bool),
                         z / dna.length, G)

    def _free_energy(self, turns, force, dna, thermal, interaction):
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


# ---- the template methods: one place checks the inputs, steps are what a model writes --


def test_overriding_a_public_method_or_leaving_a_step_out_is_a_type_error():
    with pytest.raises(TypeError, match=r"overrides DNAModel.points.*implement _points"):
        class Overrides(ParabolaRod):
            def points(self, *args):
                return None

    class NoPoints(DNAModel):
        name = "contract-no-points"

        def _buckling(self, force, dna, thermal, interaction):
            return None

    with pytest.raises(TypeError, match="abstract"):
        NoPoints()
    from supercoil.dna.interactions.base import Interaction

    with pytest.raises(TypeError, match=r"overrides Interaction.equilibrium"):
        class Bad(Interaction):
            def equilibrium(self, tension, dna):
                return None


def test_the_base_checks_the_inputs_once_for_every_model(molecule):
    dna, model = molecule.si, ParabolaRod()
    N, F = np.array([0.0, 1.0]), np.full(2, 1e-12)
    with pytest.raises(ValueError, match="one shape"):
        model.points(N, F[:1], dna, True)
    with pytest.raises(ValueError, match="turns must be finite"):
        model.points(np.array([0.0, np.nan]), F, dna, True)
    # the check is one pass (a sum): an infinity or a NaN anywhere, and a sum that
    # overflows from finite turns told apart from them
    for bad in ([1e308, 1e308, -np.inf], [np.inf, -np.inf], [1e308, np.nan, 1e308]):
        with pytest.raises(ValueError, match="turns must be finite"):
            model.points(np.array(bad), np.full(len(bad), 1e-12), dna, True)
    with pytest.raises(sc.ValidityError) as huge, np.errstate(over="ignore", invalid="ignore"):
        model.points(np.array([1e308, 1e308]), F, dna, True)  # finite: the output fails
    assert "turns must be finite" not in str(huge.value)
    with pytest.raises(sc.NoEquilibriumError, match=r"-1 pN.*positive"):
        model.buckling(np.array([-1e-12]), dna, True)
    with pytest.raises(TypeError, match=r"DNA\.si"):
        model.points(N, F, molecule, True)
    with pytest.raises(TypeError, match="thermal"):
        model.points(N, F, dna, "yes")
    with pytest.raises(ModelError, match="needs an interaction"):
        get_model("li-zhao").buckling(F[:1], dna, True, None)
    empty = model.points(np.empty(0), np.empty(0), dna, True)
    assert empty.extension.shape == (0,) and empty.free_energy.shape == (0,)
    assert model.buckling(np.empty(0), dna, True).turns.shape == (0,)


def test_a_nan_of_a_step_is_a_named_error_and_the_shared_limits_come_from_validity(molecule):
    class Holey(ParabolaRod):
        name = "contract-holey"

        def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
            p = super()._points(turns, force, dna, thermal, interaction, short_tail_length)
            return p._replace(extension=np.where(turns > 2, np.nan, p.extension))

    dna = molecule.si
    with pytest.raises(sc.ValidityError, match=r"'contract-holey' gives extension = nan at "
                                               r"force 1 pN, turns 3"):
        Holey().points(np.array([1.0, 3.0]), np.full(2, 1e-12), dna, True)
    N, F = np.array([-3.0, 3.0]), np.array([70e-12, 70e-12])
    p = ParabolaRod().points(N, F, dna, True)
    msgs = ParabolaRod().validity(N, F, p, dna, True)
    assert any("overstretches" in m for m in msgs) and any("denatures" in m for m in msgs)


def test_a_module_in_a_model_package_is_registered_by_being_there(tmp_path, monkeypatch):
    """The package's registries find their modules: adding a model adds no import line."""
    from supercoil.dna.registry import Registry

    pkg = tmp_path / "contract_pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "base.py").write_text("raise ImportError('base is not a model module')\n")
    (pkg / "rod.py").write_text(
        "from supercoil.dna.models.base import DNAModel\n\n\n"
        "class Rod(DNAModel):\n    name = 'contract-pkg-rod'\n\n"
        "    def _buckling(self, *args):\n        pass\n\n"
        "    def _points(self, *args):\n        pass\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    reg = Registry("model", DNAModel, "contract_pkg")
    assert reg.names() == ["contract-pkg-rod"]  # the imported DNAModel is not its own
    assert list(reg.package_classes()) == ["Rod"]


@pytest.mark.parametrize("inter", ["hard-core", "screened"])
def test_li_zhao_turns_at_a_tail_length_are_exact_for_any_interaction(inter, molecule):
    """li-zhao's step is exact: at the returned turns its points have that tail, L - S = l."""
    dna, model, interaction = molecule.si, get_model("li-zhao"), get_interaction(inter)
    tail = 4 * dna.bending_persistence
    n = model.turns_at_tail_length(FORCES, tail, dna, True, interaction)
    p = model.points(n, FORCES, dna, True, interaction)
    np.testing.assert_allclose(dna.length - p.plectoneme_length, tail, rtol=1e-6)
    never = ParabolaRod().turns_at_tail_length(FORCES, tail, dna, True)
    assert np.all(np.isposinf(never))  # a model that never buckles keeps its whole tail
