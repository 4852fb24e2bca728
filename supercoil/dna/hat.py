"""Hat curves of DNA in a magnetic tweezers: extension versus turns at fixed forces.

docs/theory/li-zhao.md (the paper's Example III) and docs/theory/models.md.
Unit wrappers over the DNA models (:mod:`supercoil.dna.models`): every
function takes ``model=`` (a registered name such as ``"li-zhao"``, the
default, or a :class:`~supercoil.dna.models.base.DNAModel` instance) and, for
models with a plectoneme helix, ``interaction=`` (``"hard-core"``, the
paper's, by default). The plectoneme equilibrium is solved once per force.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pandas as pd

from supercoil import display
from supercoil._checks import check_flag
from supercoil.core.dna.interface import SHORT_TAIL_PERSISTENCE_LENGTHS
from supercoil.dna import validity as _v
from supercoil.dna.interactions import DEFAULT_INTERACTION, get_interaction
from supercoil.dna.models import DEFAULT_MODEL, get_model
from supercoil.dna.plot import plot_hat_curves
from supercoil.tables import make_table, provenance
from supercoil.units import U, magnitude, quantity

__all__ = [
    "HELICAL_REPEAT",
    "PHASES",
    "buckling_turns",
    "free_energy",
    "hat_curve",
    "plot_hat_curves",
    "post_buckling_slope",
    "resolve",
]

HELICAL_REPEAT = _v.HELICAL_REPEAT  # DNA helical repeat h (m per helical turn)
#: phase labels of the ``phase`` column, indexed by the kernel's phase code
PHASES = np.array(["stretched", "plectoneme", "fully coiled"], dtype=object)
_PHASE_CATEGORIES = list(PHASES)  # the phase column is categorical: cheap for long tables
_PHASE_DTYPE = pd.CategoricalDtype(_PHASE_CATEGORIES)

_COLUMNS = ("force", "turns", "extension", "phase", "torque", "plectoneme_length",
            "supercoiling_density", "eta", "short_tail", "free_energy")
#: the hat table's units: the display units, products spelled with a space (its CSV header)
_UNITS = {k: display.unit(k).replace("*", " ") for k in _COLUMNS}


def resolve(dna, force, thermal, model, interaction):
    """Checked ``(dna SI, forces (N, 1-D), model, recording interaction)`` of a public call."""
    thermal = check_flag(thermal, "thermal")
    si = _v.check_dna(dna)
    f = _v.checked_forces(force)
    m = get_model(model)
    if interaction is None or interaction == DEFAULT_INTERACTION:
        inter = get_interaction(DEFAULT_INTERACTION)
    elif not m.uses_interaction:
        from supercoil.exceptions import ModelError

        raise ModelError(f"model {m.name!r} has no plectoneme helix state, so it takes no "
                         f"interaction (got interaction={interaction!r})")
    else:
        inter = get_interaction(interaction)
    rec = _v.StateRecorder(inter)
    (rec if m.uses_interaction else inter).check(si)  # the recorder adds the shared scales
    return si, f, thermal, m, rec


def buckling_turns(dna, force, thermal=True, model=DEFAULT_MODEL, interaction=DEFAULT_INTERACTION):
    """Turns at buckling at each force (docs/theory/models.md#buckling).

    For ``"li-zhao"``: ``N_b = C omega L / (2 pi C_eff)``, where the tail
    torque reaches the plectoneme torque.

    Returns
    -------
    Quantity [turn], number of turns (1-D, one per force). The hat
    curve buckles at ``+N_b`` and ``-N_b``.

    Warns
    -----
    ValidityWarning
        The shared DNA limits (force above 65 pN; R below the hard-core
        radius) as :func:`plectoneme_equilibrium` gives them.
    """
    si, f, thermal, m, inter = resolve(dna, force, thermal, model, interaction)
    b = m.buckling(f, si, thermal, inter)
    _v.warn(_v.force_messages(f) + inter.messages(si), stacklevel=2)
    return quantity(b.turns, U.turn)


def post_buckling_slope(dna, force, thermal=True, model=DEFAULT_MODEL,
                        interaction=DEFAULT_INTERACTION):
    """Post-buckling slope ``dz/dN`` for N > N_b, in nm per turn, at each force.

    For ``"li-zhao"``: ``dz/dN = -2 pi zeta_inf / D`` with
    ``D = tau - (C/C_eff - 1) omega`` and ``zeta_inf = 1 - Q^(-1/2)/2``
    (athermal: ``-2 pi / tau``); derivation in docs/theory/li-zhao.md#slope.
    The slope for N < -N_b is the opposite.

    Returns
    -------
    Quantity [nm/turn] (negative), 1-D.

    Warns
    -----
    ValidityWarning
        The shared DNA limits, and (li-zhao, thermal) where zeta's long-tail
        factor is <= 0 (the slope would be positive: 0.0954-0.1218 pN for the
        seed set) or < 0.5 (the Moroz-Nelson expansion has not converged).
    """
    si, f, thermal, m, inter = resolve(dna, force, thermal, model, interaction)
    with np.errstate(invalid="ignore"):  # an undefined slope is raised as ValidityError below
        b = m.buckling(f, si, thermal, inter)
        msgs = m.slope_validity(f, b, si, thermal) + inter.messages(si)
    if not np.all(np.isfinite(b.slope)):
        from supercoil.exceptions import ValidityError

        i = np.flatnonzero(~np.isfinite(b.slope))[0]
        raise ValidityError(f"the post-buckling slope is not defined at force "
                            f"{display.text(f[i], 'force')} (model {m.name!r})")
    _v.warn(msgs, stacklevel=2)
    return quantity(b.slope * display.factor("extension"), U.nm_per_turn)


def _points(dna, force, turns, thermal, model, interaction, short_tail_length, stacklevel):
    si, f, thermal, m, inter = resolve(dna, force, thermal, model, interaction)
    n = _v.checked_turns(turns, si)
    if short_tail_length is None:
        short = None
    else:
        short = magnitude(short_tail_length, U.m, "short_tail_length")
        if not (np.ndim(short) == 0 and short >= 0 and np.isfinite(short)):
            raise ValueError(f"short_tail_length must be a non-negative finite scalar, "
                             f"got {short_tail_length}")
    F = _repeated(f, n.size)
    N = _tiled(n, f.size, turns)
    hp = m.points(N, F, si, thermal, inter, short)  # no point: an empty table, no kernel call
    msgs = m.validity(N, F, hp, si, thermal) + inter.messages(si) if N.size else []
    _v.warn(msgs, stacklevel=stacklevel + 1)
    return si, F, N, hp, m, inter.interaction, thermal, short


def _repeated(f, size):
    """The per-point forces: each force ``size`` times, force-major.

    One force: a read-only broadcast view (no array written: 8 MB fewer at 1e6
    points; the models only read the forces).
    """
    if f.size == 1:
        return np.broadcast_to(f, (size,))
    return np.repeat(f, size)


def _tiled(n, times, given):
    """``n`` repeated ``times`` times: the turns column, never a view of the caller's ``given``.

    One force and a fresh ``n`` (read from a list or converted from a
    quantity): ``n`` itself, no copy.
    """
    if times == 1 and n.flags.owndata and n.flags.writeable:
        src = getattr(given, "magnitude", given)
        if not (isinstance(src, np.ndarray) and np.may_share_memory(n, src)):
            return n
    return np.tile(n, times)


def free_energy(dna, force, turns, thermal=True, model=DEFAULT_MODEL,
                interaction=DEFAULT_INTERACTION):
    """Total free energy ``G(N, F)`` at fixed force (pN nm), force-major like :func:`hat_curve`.

    ``z = -dG/dF`` and ``M = (1/2 pi) dG/dN`` (docs/theory/free-energy.md).

    Raises
    ------
    ModelError
        For models without one free energy (the thermal ``"li-zhao"``
        construction).
    ValueError, ValidityError
        Turns not finite; ``|N| > L / h`` (see :func:`hat_curve`). An
        empty force or turns array gives an empty result.
    """
    si, f, thermal, m, inter = resolve(dna, force, thermal, model, interaction)
    n = _v.checked_turns(turns, si)
    F = np.repeat(f, n.size)
    N = np.tile(n, f.size)
    g = m.free_energy(N, F, si, thermal, inter)
    _v.warn(_v.force_messages(f) + inter.messages(si), stacklevel=2)
    return display.quantity(g, "free_energy")


def hat_curve(dna, force, turns, thermal=True, short_tail_length=None, model=DEFAULT_MODEL,
              interaction=DEFAULT_INTERACTION):
    """Hat curves: extension, torque and phase versus turns at fixed forces.

    Built as docs/theory/li-zhao.md#hat-curve (default model): stretched phase (torque
    ``C_eff 2 pi N / L``, ``z = zeta L``), buckling where the torques match,
    plectoneme phase from the linking balance
    ``2 pi |N| = (C/C_eff) omega (L - S) + (omega + tau) S`` with
    ``z = zeta(C omega, L - S) (L - S)``, fully coiled (``z = 0``) for S >= L.

    Parameters
    ----------
    dna : DNA
    force : Quantity [force]
        One force or a 1-D array of forces.
    turns : array-like or Quantity
        Turns N (plain numbers, dimensionless, or an angle unit), 1-D.
    thermal : bool
        Moroz-Nelson corrections; ``False`` gives ``C_eff = C``, ``zeta = 1``
        and computes no thermal term.
    short_tail_length : Quantity [length], optional
        Tails shorter than this are flagged ``short_tail`` (default 3 bending
        persistence lengths).
    model : str or DNAModel
        The construction (default ``"li-zhao"``, the paper's); see
        :func:`supercoil.available_models`.
    interaction : str or Interaction
        The inter-strand interaction of the plectoneme (default
        ``"hard-core"``, the paper's); models without a plectoneme helix
        state take none.

    Returns
    -------
    pandas.DataFrame
        One row per (force, turns), force-major, with columns ``force`` [pN],
        ``turns``, ``extension`` [nm], ``phase`` ("stretched", "plectoneme",
        "fully coiled"), ``torque`` [pN nm] (sign of N), ``plectoneme_length``
        [nm], ``supercoiling_density`` (``sigma = N h / L``, h = 3.57 nm),
        ``eta`` (``2 pi N xi_T / L``) and ``short_tail`` (bool);
        ``attrs["units"]`` and ``attrs["provenance"]``.

    Raises
    ------
    TypeError
        ``dna`` not a DNA, ``thermal`` not True/False, turns or force not
        real numbers (text, None, complex), a list mixing quantities and
        plain numbers.
    ValueError
        Turns or force not finite; turns not 1-D. (An empty force or turns
        array gives a table of no rows with the same columns and units.)
    NoEquilibriumError
        Naming the force, where no plectoneme equilibrium exists.
    ValidityError
        ``|N|`` above the molecule's helical turns ``Lk0 = L / h`` (h = 3.57
        nm, supercoiling density ``|sigma| > 1``), where no model applies;
        (thermal) naming force and torque where zeta's bracket is not positive:
        for the seed set in the plectoneme phase below 0.0954 pN, and above
        43.95 pN, where the plectoneme torque exceeds what the fluctuating tail
        can carry (``M_p^2/4 > B T - (kT)^2/32``); the athermal curve stays
        defined there.

    Warns
    -----
    ValidityWarning
        For forces above 65 pN (B-DNA overstretches; the model is
        inextensible); for negative turns above 0.8 pN (real DNA denatures
        there; the model ignores it); where zeta leaves (0, 1] at a point whose tail is not
        flagged short; and where zeta's long-tail factor ``1 - Q^(-1/2)/2`` is
        not positive (the extension would grow with turns), or below 0.5 (the
        Moroz-Nelson expansion in 1/sqrt(Q) has not converged: bracket Q < 1).
        With the seed set and the default short-tail length: the bracket is
        negative below 0.0954 pN (error), the long-tail factor is <= 0 below
        0.1218 pN, zeta > 1 at a 3 A tail below 0.1354 pN, and Q < 1 in the
        plectoneme phase below 0.201 pN; above 0.201 pN (and below 43.95 pN)
        the thermal curve is valid.
    """
    si, F, N, hp, m, inter, thermal, short = _points(dna, force, turns, thermal, model,
                                                     interaction, short_tail_length, 2)
    L = si.length
    if short is None:
        short = SHORT_TAIL_PERSISTENCE_LENGTHS * si.bending_persistence
    # The checks above read the SI arrays; now each fresh array becomes its display-unit
    # column in place (no second copy: the peak memory stays near the table's own).
    own = _Owned(N)
    columns = {
        "force": (np.full(F.size, F[0] * display.factor("force")) if F.strides == (0,)
                  and F.size else own.scaled(F, display.factor("force"))),
        "turns": N,
        "extension": own.scaled(hp.extension, display.factor("extension")),
        "phase": pd.Categorical.from_codes(hp.phase, dtype=_PHASE_DTYPE),
        "torque": own.scaled(hp.torque, display.factor("torque")),
        "plectoneme_length": own.scaled(hp.plectoneme_length, display.factor("plectoneme_length")),
        "supercoiling_density": N * (HELICAL_REPEAT / L),
        "eta": N * (2.0 * np.pi * si.wlc_persistence / L),
        "short_tail": hp.short_tail,
    }
    units = dict(_UNITS)
    if m.has_free_energy(thermal):
        g = hp.free_energy if hp.free_energy is not None else m.free_energy(N, F, si, thermal,
                                                                             inter)
        columns["free_energy"] = own.scaled(np.asarray(g, dtype=float),
                                            display.factor("free_energy"))
    else:
        units.pop("free_energy")
    return make_table(
        columns,
        units,
        provenance(
            _parameters(dna),
            scene="hat curve (docs/theory/models.md)",
            model=m.name,
            model_parameters={k: f"{q:.12g~}" for k, q in m.quantities().items()},
            model_options=m.options(),
            interaction=inter.name if m.uses_interaction else None,
            thermal=bool(thermal),
            short_tail_length=display.text(short, "length"),
            helical_repeat=display.text(HELICAL_REPEAT, "length"),
        ),
    )


class _Owned:
    """Scales a model's fresh result arrays in place, each at most once (else copies).

    An array is scaled in place only if it owns its data, is writeable, is a
    float64 array and has not been seen before (a model returning one array for
    two fields, or the turns column, gets a scaled copy instead).
    """

    def __init__(self, *seen):
        self.seen = {id(a) for a in seen}

    def scaled(self, a, factor):
        fresh = (isinstance(a, np.ndarray) and a.dtype == np.float64 and a.flags.owndata
                 and a.flags.writeable and id(a) not in self.seen)
        if not fresh:
            return np.multiply(a, factor)
        self.seen.add(id(a))
        return np.multiply(a, factor, out=a)


@lru_cache(maxsize=32)
def _parameters(dna):
    """``dna.as_dict()`` once per molecule (formatting pint units is slow)."""
    return dna.as_dict()
