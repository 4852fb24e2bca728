"""The optional compiled hat-curve kernel (supercoil.core.dna.li_zhao_numba, numba) against numpy.

The numpy path (:func:`supercoil.core.dna.li_zhao_numpy.fill_block`) is the reference:
the fused loop performs the same floating-point operations in the same order,
so every output must agree to rounding (in practice bit for bit), on every
phase, at block seams, with one force per block and with mixed forces, and it
must fail where the numpy path fails, with the same named errors. numba comes
with the ``test`` extra (these tests fail without it); the missing-numba error
is checked by hiding numba.
"""

import sys

import numpy as np
import pytest

from supercoil.core.dna import interface as iface
from supercoil.core.dna import li_zhao as hc
from supercoil.core.dna import li_zhao_numba
from supercoil.exceptions import ValidityError
from supercoil.units import BOLTZMANN

KT = BOLTZMANN * 300.0
B = 48e-9 * KT
C = 86e-9 * KT
L = 750e-9
ARGS = (L, B, C, KT, 1.75e-9)

# every phase: stretched, plectoneme, fully coiled, short tails; three forces
F3 = np.repeat(np.array([0.4, 1.2, 3.0]) * 1e-12, 1201)
N3 = np.tile(np.linspace(-60.0, 60.0, 1201), 3)


def _agree(a, b):
    """Each field equal to rounding (1 ulp-scale), same dtypes, same None fields."""
    for name, x, y in zip(a._fields, a, b, strict=True):
        if x is None:
            assert y is None, name
            continue
        if name == "summary":  # reductions of equal arrays: equal (NaN athermal)
            np.testing.assert_equal(tuple(y), tuple(x))
            continue
        assert x.dtype == y.dtype, name
        if x.dtype.kind == "f":
            np.testing.assert_allclose(y, x, rtol=4e-16, atol=1e-300, err_msg=name)
        else:
            np.testing.assert_array_equal(y, x, err_msg=name)


@pytest.fixture
def numba():
    """numba itself: the ``test`` extra installs it, so a missing numba fails, never skips."""
    import numba

    return numba


@pytest.mark.parametrize("thermal", [True, False])
def test_compiled_equals_numpy_on_every_phase(numba, thermal):
    a = hc.hat_curve_points(N3, F3, *ARGS, thermal=thermal, fast=False)
    b = hc.hat_curve_points(N3, F3, *ARGS, thermal=thermal, fast=True)
    assert set(np.unique(a.phase)) == {iface.STRETCHED, iface.PLECTONEME, iface.FULLY_COILED}
    assert a.short_tail.any() and not a.short_tail.all()
    _agree(a, b)


def test_compiled_equals_numpy_with_mixed_forces_and_seams(numba, monkeypatch):
    """Interleaved forces (per-point constants) and blocks cut inside a force's run."""
    rng = np.random.default_rng(1)
    order = rng.permutation(F3.size)
    F, N = F3[order], N3[order]
    monkeypatch.setattr(hc, "BLOCK", 97)
    for forces, turns in ((F, N), (F3, N3)):
        _agree(hc.hat_curve_points(turns, forces, *ARGS, fast=False),
               hc.hat_curve_points(turns, forces, *ARGS, fast=True))


def test_environment_variable_selects_the_compiled_kernel(numba, monkeypatch):
    calls = []
    real = li_zhao_numba.fill
    monkeypatch.setattr(li_zhao_numba, "fill", lambda *a: calls.append(1) or real(*a))
    hc.hat_curve_points(N3[:50], F3[:50], *ARGS)
    assert calls == []  # the numpy path is the default
    monkeypatch.setenv(li_zhao_numba.ENV, "1")
    fast = hc.hat_curve_points(N3[:50], F3[:50], *ARGS)
    assert calls == [1]
    _agree(hc.hat_curve_points(N3[:50], F3[:50], *ARGS, fast=False), fast)
    hc.hat_curve_points(N3[:50], F3[:50], *ARGS, fast=False)  # the argument wins
    assert calls == [1]


def test_compiled_kernel_fails_like_numpy(numba):
    with pytest.raises(ValueError, match="turns must be finite"):
        hc.hat_curve_points([1.0, np.nan], [1e-12, 1e-12], *ARGS, fast=True)
    # below 0.0954 pN the plectoneme torque leaves zeta's bracket: the numpy path's error
    with pytest.raises(ValidityError) as numpy_err:
        hc.hat_curve_points([10.0], [0.09e-12], *ARGS, fast=False)
    with pytest.raises(ValidityError) as fast_err:
        hc.hat_curve_points([10.0], [0.09e-12], *ARGS, fast=True)
    assert str(fast_err.value) == str(numpy_err.value)
    assert "0.09 pN" in str(fast_err.value)
    # athermal is defined there, and equal
    _agree(hc.hat_curve_points([10.0], [0.09e-12], *ARGS, thermal=False, fast=False),
           hc.hat_curve_points([10.0], [0.09e-12], *ARGS, thermal=False, fast=True))


def test_asking_for_the_compiled_kernel_without_numba_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba raises ImportError
    monkeypatch.setattr(li_zhao_numba, "_KERNEL", None)
    assert not li_zhao_numba.available()
    with pytest.raises(ImportError, match=r"supercoil\[fast\]"):
        hc.hat_curve_points([1.0], [1e-12], *ARGS, fast=True)
    monkeypatch.setenv(li_zhao_numba.ENV, "1")
    with pytest.raises(ImportError, match="SUPERCOIL_FAST"):
        hc.hat_curve_points([1.0], [1e-12], *ARGS)
    assert hc.hat_curve_points([1.0], [1e-12], *ARGS, fast=False).extension[0] > 0


def test_wanted_reads_the_argument_then_the_environment(monkeypatch):
    monkeypatch.delenv(li_zhao_numba.ENV, raising=False)
    assert not li_zhao_numba.wanted(None)
    assert li_zhao_numba.wanted(True) and not li_zhao_numba.wanted(False)
    for value, expected in (("1", True), ("0", False), ("", False), ("yes", False)):
        monkeypatch.setenv(li_zhao_numba.ENV, value)
        assert li_zhao_numba.wanted(None) is expected
    assert not li_zhao_numba.wanted(False)
