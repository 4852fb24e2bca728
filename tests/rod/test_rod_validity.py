"""supercoil.rod.validity: the checks every rod scene shares, and that the scenes use them."""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.core.rod import contact as sco
from supercoil.rod import validity as rv

u = sc.ureg


def test_hard_contact_warning_at_the_hertz_limit():
    """b / r = sin^2 a / sqrt(cos 2a) = 1 at cos 2a = 3 - 2 sqrt 2 (alpha = 0.699 rad)."""
    a_lim = 0.5 * np.arccos(3 - 2 * np.sqrt(2))
    assert sco.contact_width_ratio(a_lim) == pytest.approx(1.0, rel=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert rv.warn_hard_contact(np.array([0.3, a_lim * (1 - 1e-9)]), "test") is None
    with pytest.warns(sc.ValidityWarning, match=r"test scene.*b = 1\.\d+ r exceeds"):
        msg = rv.warn_hard_contact(np.array([0.3, a_lim * 1.01]), "test scene")
    assert "0.699 rad" in msg


def test_check_finite_names_the_field_value_and_position():
    rv.check_finite({"pitch [mm]": np.array([1.0, 2.0])}, "fine")
    with pytest.raises(sc.ValidityError, match=r"'pitch \[mm\]' is inf at index 2 \(N = 1e-300\)"):
        rv.check_finite({"alpha": [0.1], "pitch [mm]": [1.0, 2.0, np.inf, np.nan]},
                        "N = 1e-300")


def test_check_finite_scaled_finds_what_the_scaled_product_overflows():
    # finite in m but 1e306 m is inf in mm: caught from the extremes, with
    # check_finite's message on the product (first field first)
    rv.check_finite_scaled({"pitch [mm]": (np.array([1.0, -1e305]), 1e3),
                            "none": (np.array([]), 1e3)}, "fine")
    with pytest.raises(sc.ValidityError, match=r"'pitch \[mm\]' is inf at index 1 \(N = 1\)"):
        rv.check_finite_scaled({"pitch [mm]": (np.array([1.0, 1e306, np.nan]), 1e3),
                                "other": (np.array([np.nan]), 1.0)}, "N = 1")
    with pytest.raises(sc.ValidityError, match=r"'other' is nan at index 0"):
        rv.check_finite_scaled({"pitch [mm]": (np.array([1.0]), 1e3),
                                "other": (np.array([np.nan, 1.0]), 1.0)}, "N = 1")


def test_no_friction_warning_names_the_scene():
    with pytest.warns(sc.ValidityWarning, match="no-slip condition .* of the rough helix"):
        rv.warn_no_friction("rough helix", "slip_onset is None")


@pytest.mark.parametrize("scene", ["smooth", "rough", "spinning", "design"])
def test_every_rod_scene_warns_through_the_shared_check(monkeypatch, scene):
    """Each scene calls rod.validity.warn_hard_contact with its tilts (one place)."""
    rod = sc.ElasticRod(1.0 * u.mm, 56.7 * u.cm, 4.2 * u.MPa, 1.51 * u.MPa, 0.5)
    seen = []
    for mod in ("smooth", "rough", "spinning", "design"):
        monkeypatch.setattr(f"supercoil.rod.{mod}.warn_hard_contact",
                            lambda a, where, **kw: seen.append((np.max(a), where)))
    calls = {
        "smooth": lambda: sc.smooth_helix(rod, 40, 10 * u.cm),
        "rough": lambda: sc.rough_helix(rod, 40),
        "spinning": lambda: sc.twist_spinning(rod, 40, 0.1 * u.N),
        "design": lambda: sc.design_twist_schedule(rod, lambda s: 20 * u.mm + 0 * s,
                                                  slack_max=20 * u.cm),
    }
    calls[scene]()
    assert len(seen) == 1 and 0 < seen[0][0] < np.pi / 4
