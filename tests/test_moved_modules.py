"""The modules moved in 0.2 stay importable for one release, with a DeprecationWarning."""

import importlib
import sys

import pytest

import supercoil as sc

MOVED = {"fitting": "supercoil.dna.fitting", "hat": "supercoil.dna.hat",
         "plectoneme": "supercoil.dna.plectoneme", "tweezers_data": "supercoil.dna.tweezers",
         "rough": "supercoil.rod.rough", "smooth": "supercoil.rod.smooth",
         "spinning": "supercoil.rod.spinning", "design": "supercoil.rod.design"}


@pytest.fixture
def fresh(monkeypatch):
    """No shim imported yet (an import caches the module and sets the package attribute)."""
    for old in MOVED:
        monkeypatch.delitem(sys.modules, f"supercoil.{old}", raising=False)
        if old in vars(sc):  # (hasattr would call the warning __getattr__)
            monkeypatch.delattr(sc, old)


@pytest.mark.parametrize("old", sorted(MOVED))
def test_attribute_warns_and_names_the_new_path(old, fresh):
    with pytest.warns(DeprecationWarning, match=MOVED[old].replace(".", r"\.")):
        mod = getattr(sc, old)
    assert mod is importlib.import_module(MOVED[old])
    assert old not in sc.__all__


@pytest.mark.parametrize("old", sorted(MOVED))
def test_import_warns_and_names_the_new_path(old, fresh):
    with pytest.warns(DeprecationWarning, match=MOVED[old].replace(".", r"\.")):
        shim = importlib.import_module(f"supercoil.{old}")
    new = importlib.import_module(MOVED[old])
    public = getattr(new, "__all__", [])
    for name in public:
        assert getattr(shim, name) is getattr(new, name)


def test_fitting_valid_turns_range_through_the_old_paths(fresh):
    from supercoil.dna.fitting import valid_turns_range

    with pytest.warns(DeprecationWarning, match=r"supercoil\.dna\.fitting"):
        assert sc.fitting.valid_turns_range is valid_turns_range
    with pytest.warns(DeprecationWarning, match=r"supercoil\.dna\.fitting"):
        import supercoil.fitting
    assert supercoil.fitting.valid_turns_range is valid_turns_range


def test_unknown_attribute_still_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'nonexistent'"):
        sc.nonexistent  # noqa: B018
