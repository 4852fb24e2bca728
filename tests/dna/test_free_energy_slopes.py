"""Closed-form slopes of the free-energy hat curve in the turns (core/dna/free_energy_slopes,
docs/theory/free-energy.md FE10), against central differences of the model's own points.

Reference: ``(p(N + h) - p(N - h)) / 2h`` of the returned extension and torque at
``h = 1e-4`` turn (no formula of the slopes reused), at points whose phase is the same at
``N -/+ h``, on an 800 nm molecule over +-80 turns (all three phases) at 1 and 2 pN.
Measured over 16 cases (thermal and athermal, hard-core and screened, with and without
the loop): within 8.9e-11 of the largest slope for dz/dN and 4.0e-11 for dM/dN (the
differences' rounding and truncation); asserted at 1e-7.
"""

import numpy as np
import pytest

import supercoil as sc
from supercoil.core.dna.interface import FULLY_COILED, PLECTONEME, STRETCHED
from supercoil.dna.interactions import get_interaction
from supercoil.dna.models import get_model

H = 1e-4


def _dna(length_nm=800.0):
    u = sc.ureg
    return sc.load_parameters("dna_150mM_nacl").replace(length=length_nm * u.nm).si


def _case(end_loop, interaction, thermal, force):
    model, inter, dna = get_model("free-energy", end_loop=end_loop), \
        get_interaction(interaction), _dna()
    half = np.linspace(0.0, 80.0, 801)
    turns = np.concatenate([-half[:0:-1], half])  # symmetric bit for bit
    f = np.full(turns.size, force)
    pts = model.points(turns, f, dna, thermal, inter)
    dz, dM = model.turn_slopes(turns, f, dna, thermal, inter, pts)
    lo, hi = (model.points(turns + s, f, dna, thermal, inter) for s in (-H, H))
    same = (lo.phase == pts.phase) & (hi.phase == pts.phase)
    fd_z = (hi.extension - lo.extension) / (2 * H)
    fd_M = (hi.torque - lo.torque) / (2 * H)
    return turns, pts, dz, dM, same, fd_z, fd_M


# hard-core in every combination; screened (its fully coiled points cost a root solve each
# call: about 0.6 s for the three calls of a case) thermal, with and without the loop; at
# 0.5 pN the end loop's 800 nm molecule is too short (a named ValidityError)
CASES = [(loop, "hard-core", thermal, force) for loop in (False, True)
         for thermal in (True, False) for force in (1e-12, 2e-12)] + [
    (False, "screened", True, 1e-12), (True, "screened", True, 2e-12)]


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize(("end_loop", "interaction", "thermal", "force"), CASES)
def test_slopes_match_central_differences_in_every_phase(end_loop, interaction, thermal,
                                                         force):
    _, pts, dz, dM, same, fd_z, fd_M = _case(end_loop, interaction, thermal, force)
    for code in (STRETCHED, PLECTONEME, FULLY_COILED):  # every phase is in the range
        assert np.count_nonzero(same & (pts.phase == code)) > 20, code
    scale_z = np.max(np.abs(fd_z[same]))
    assert np.max(np.abs(dz - fd_z)[same]) <= 1e-7 * scale_z
    # fully coiled: z = 0 there, and dM/dN is NaN (the branch's slope is not at hand)
    coiled = pts.phase == FULLY_COILED
    assert np.all(dz[coiled] == 0.0) and np.all(np.isnan(dM[coiled]))
    ok = same & ~coiled
    assert np.max(np.abs(dM - fd_M)[ok]) <= 1e-7 * np.max(np.abs(fd_M[ok]))
    # the plateau: no torque change, and the post-buckling slope of the model's buckling
    plect = pts.phase == PLECTONEME
    assert np.all(dM[plect] == 0.0)
    b = get_model("free-energy").buckling(np.array([force]), _dna(), thermal,
                                          get_interaction(interaction))
    np.testing.assert_allclose(np.abs(dz[plect]), abs(b.slope[0]), rtol=1e-13)


@pytest.mark.filterwarnings("ignore")
def test_slopes_are_odd_and_even_in_the_turns():
    """z is even in N, M odd: dz/dN odd, dM/dN even, bit for bit."""
    turns, _, dz, dM, *_ = _case(False, "hard-core", True, 1.2e-12)
    assert np.array_equal(dz, -dz[::-1])
    assert np.array_equal(dM, dM[::-1], equal_nan=True)
    assert dz[turns.size // 2] == 0.0  # N = 0: the top of the hat


def test_slopes_reject_what_the_points_reject():
    model, inter, dna = get_model("free-energy"), get_interaction("hard-core"), _dna()
    turns, f = np.zeros(3), np.full(3, 1e-12)
    pts = model.points(turns, f, dna, True, inter)
    with pytest.raises(ValueError, match="1-D arrays of one shape"):
        model.turn_slopes(turns, f[:2], dna, True, inter, pts)
    with pytest.raises(ValueError, match="force"):
        model.turn_slopes(turns, -f, dna, True, inter, pts)
