"""Validity checks shared by every public DNA function (docs/theory/limits.md).

One place for the limits of the DNA models: the input checks (a DNA, a finite
force), the shared physical limits (overstretching above 65 pN, denaturation
under negative turns above 0.8 pN, the strands pressed inside the hard core,
a stretched tail carrying more than the Euler torque, an extension longer than
the contour length) and the emission of the warnings. Each text is written
here once: :meth:`~supercoil.dna.models.base.DNAModel.validity` applies the
shared point limits (:func:`point_messages`) to every model and adds the
model's own (e.g. the Moroz-Nelson bracket of ``"li-zhao"``); the public layer
and the fits issue them (:func:`warn`).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from supercoil import display
from supercoil._checks import check_material, check_scale
from supercoil.core.blocks import extremes
from supercoil.core.dna.interface import DENATURATION_FORCE, OVERSTRETCHING_FORCE
from supercoil.dna.material import DNA
from supercoil.exceptions import NoEquilibriumError, ValidityWarning
from supercoil.units import U, as_turns, magnitude

__all__ = [
    "DENATURATION_FORCE",
    "OVERSTRETCHING_FORCE",
    "StateRecorder",
    "check_dna",
    "check_finite_output",
    "check_hard_core_radius",
    "check_interaction",
    "check_positive_forces",
    "checked_forces",
    "checked_turns",
    "denaturation_messages",
    "extension_messages",
    "force_messages",
    "plectoneme_messages",
    "point_messages",
    "summary_of",
    "tail_torque_messages",
    "warn",
]


#: highest temperature (K) of the DNA models: double-stranded DNA melts near 360 K, the
#: elastic models (B = A kT, C = C_t kT, the Moroz-Nelson term C kT / (4 B sqrt(B F)))
#: have no meaning far above, and near 1e150 K their products leave the float range
MAX_TEMPERATURE = 1e4

#: shortest contour length (m) of the DNA models: one base pair (0.34 nm); below it the
#: twist density 2 pi N / L of any turns leaves the float range (1e-300 nm: inf x 0 at N = 0)
MIN_LENGTH = 0.34e-9


def check_dna(dna):
    """The SI view of ``dna``; TypeError naming the argument if it is not a DNA.

    ValidityError naming the temperature above :data:`MAX_TEMPERATURE` or the length
    below :data:`MIN_LENGTH`.
    """
    si = check_material(dna, DNA, "dna")
    if si.length >= MIN_LENGTH and si.temperature <= MAX_TEMPERATURE:
        return si  # the usual case, without formatting the limits below
    check_scale(display.to_display(si.length, "length"), "the contour length (nm)",
                lo=display.to_display(MIN_LENGTH, "length"),
                why="a DNA shorter than one base pair has no double helix")
    check_scale(si.temperature, "the temperature (K)",
                hi=MAX_TEMPERATURE, why="double-stranded DNA melts near 360 K; the elastic "
                "models have no meaning far above it")
    return si


def checked_forces(force, one_d=True):
    """Force magnitudes in N (finite, positive; 1-D if ``one_d``), errors naming ``force``.

    Raises
    ------
    ValueError
        Not finite; not 1-D (``one_d``).
    NoEquilibriumError
        A force <= 0 (a ValueError too): every DNA model describes a molecule
        stretched by a positive tension (models differ in what else they need).
    """

    f = magnitude(force, U.N, "force")
    if np.iscomplexobj(f):
        raise TypeError("force must be real")
    check_positive_forces(f, force)
    if one_d:
        f = np.atleast_1d(f)
        if f.ndim != 1:
            raise ValueError(f"force must be a scalar or 1-D, got shape {f.shape}")
    return f


def check_positive_forces(f, given=None):
    """ValueError if a force (N, float array) is not finite; NoEquilibriumError if <= 0.

    The one text of the force rule, for the public functions (``given`` is the caller's
    argument, shown in the message) and for the model interface's float level.
    """
    f = np.asarray(f)
    if f.size == 0:
        return
    # NaN propagates into both; the array methods and math.isfinite: a few microseconds
    # fewer per call than np.min and np.isfinite (one-force calls pay it twice)
    lo, hi = extremes(f) if f.ndim == 1 else (f.min(), f.max())
    if not (math.isfinite(lo) and math.isfinite(hi)):
        shown = given if given is not None else f[~np.isfinite(f)].flat[0]
        raise ValueError(f"force must be finite, got {shown}")
    if lo <= 0:
        bad = float(f[f <= 0].flat[0])
        raise NoEquilibriumError(f"no equilibrium at force {display.text(bad, 'force')}: the force "
                                 "must be positive (a molecule stretched by a tension)")


#: DNA helical repeat h (m per helical turn, 10.5 bp): Lk_0 = L / h
HELICAL_REPEAT = 3.57e-9


def checked_turns(turns, dna):
    """Turns N (1-D float array) for a DNA function: real, finite, |sigma| <= 1 (may be empty).

    One check for every DNA function taking turns (:func:`~supercoil.units.as_turns`
    reads plain numbers as turns and converts angle units).

    Raises
    ------
    TypeError
        Not numbers (text, None, complex).
    ValueError
        Not 1-D, NaN or infinite. An empty array is returned as it is (the
        callers give an empty result).
    ValidityError
        ``|N| > Lk_0 = L / h`` (supercoiling density |sigma| > 1, h = 3.57 nm): more
        turns than the molecule has helical turns, where no model applies (and
        the models' arithmetic would overflow for absurd N such as 1e300).
    """
    from supercoil.exceptions import ValidityError

    n = np.atleast_1d(as_turns(turns, "turns"))
    if n.ndim != 1:
        raise ValueError(f"turns must be a scalar or 1-D, got shape {n.shape}")
    if n.size == 0:
        return n.astype(float)
    lo, hi = n.min(), n.max()  # two reductions, no temporaries: NaN propagates, inf shows
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise ValueError(f"turns must be finite, got {n[~np.isfinite(n)][0]!r}")
    lk0 = dna.length / HELICAL_REPEAT
    if max(-lo, hi) > lk0:
        big = np.abs(n) > lk0
        raise ValidityError(
            f"turns {n[big][0]:.6g}: |N| exceeds the molecule's helical turns Lk0 = L/h = "
            f"{lk0:.6g} (supercoiling density |sigma| > 1, h = 3.57 nm); no model applies")
    return n


def check_finite_output(model, force, values, turns=None, allow_inf=False):
    """ValidityError naming the model, force (and turns) where a model's output is not finite.

    ``values`` maps output names to SI arrays of the shape of ``force``; the
    models are expected to raise their own named errors first, so this is the
    net under every model (a result never carries a silent NaN or inf).
    ``allow_inf`` lets +-inf through (a buckling turns of inf: never buckles).
    """
    from supercoil.exceptions import ValidityError

    for name, x in values.items():
        x = np.asarray(x)
        if x.dtype.kind != "f" or x.size == 0 or _all_finite(x, allow_inf):
            continue  # the common case: two reductions, no mask
        bad = np.isnan(x) if allow_inf else ~np.isfinite(x)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            at = f"force {display.text(np.asarray(force).flat[i], 'force')}"
            if turns is not None:
                at += f", turns {np.asarray(turns).flat[i]:.6g}"
            raise ValidityError(f"model {model.name!r} gives {name} = {float(x.flat[i])!r} at "
                                f"{at}: outside the model's range (no finite result)")


def _all_finite(x, allow_inf=False):
    """All of ``x`` finite (or, with ``allow_inf``, not NaN), from its min and max."""
    lo, hi = x.min(), x.max()  # NaN propagates into both
    if allow_inf:
        return not (np.isnan(lo) or np.isnan(hi))
    return bool(np.isfinite(lo) and np.isfinite(hi))


def warn(messages, stacklevel=3):
    """Issue each message once as a ValidityWarning."""
    for m in dict.fromkeys(messages):
        warnings.warn(m, ValidityWarning, stacklevel=stacklevel + 1)


def force_messages(force):
    """Forces above the B-DNA overstretching plateau (~65 pN)."""
    f = np.asarray(force)
    hi = _extreme(f, np.max) if f.size else 0.0  # one reduction (the points' forces: no mask)
    if hi <= OVERSTRETCHING_FORCE:
        return []
    return [f"force {display.text(hi, 'force')} is above "
            f"{display.text(OVERSTRETCHING_FORCE, 'force', 'g')}, where B-DNA overstretches; "
            "the model (inextensible DNA) ignores it"]


def denaturation_messages(force, turns, turns_min=None):
    """Negative turns above 0.8 pN, where real DNA denatures.

    ``turns_min``: the smallest turns, if the caller knows it (a kernel's summary).
    """
    force, turns = np.asarray(force), np.asarray(turns)
    if force.size == 0 or _extreme(force, np.max) <= DENATURATION_FORCE:
        return []  # cheap reductions first: the mask below costs three passes
    if (turns.min() if turns_min is None else turns_min) >= 0:
        return []
    den = (turns < 0) & (force > DENATURATION_FORCE)
    if not np.any(den):
        return []
    return [f"negative turns at {display.text(np.asarray(force)[den].max(), 'force')} "
            "(> 0.8 pN): real DNA denatures under negative supercoiling there; the model "
            "ignores denaturation"]


def point_messages(turns, force, points, dna, describes_denaturation=False):
    """The shared limits at hat-curve points (SI): overstretching, denaturation (unless
    the model describes it), an extension outside [0, L], a tail torque above Euler's.

    :meth:`supercoil.dna.models.base.DNAModel.validity` applies them to every model's
    points (docs/theory/limits.md#dna), before the model's own messages.
    """
    s = summary_of(points)
    known = None if s is None or np.isnan(s.turns_min) else s.turns_min
    denat = [] if describes_denaturation else denaturation_messages(force, turns, known)
    return (force_messages(force) + denat + extension_messages(force, turns, points, dna)
            + tail_torque_messages(force, turns, points, dna))


def plectoneme_messages(state, dna, hard_core_radius=None):
    """The superhelix radius below the hard-core radius (strands pressed into each other)."""
    r0 = dna.radius if hard_core_radius is None else hard_core_radius
    R = np.atleast_1d(state.radius)
    tight = R < r0
    if not np.any(tight):
        return []
    f = np.atleast_1d(state.force)[tight]
    return [f"at {display.text(f.max(), 'force')} the superhelix radius R = "
            f"{display.text(R[tight][np.argmax(f)], 'length', '.4g')} < r0 = "
            f"{display.text(r0, 'length')}: the strands are pressed inside the hard-core radius "
            "(above ~30 pN for the seed set), where the "
            "interaction is extrapolated"]


def tail_torque_messages(force, turns, points, dna):
    """A stretched tail carrying more than the Euler buckling torque ``2 sqrt(B F)``."""
    force = np.asarray(force)
    if force.size == 0:
        return []
    lo, hi = _range(points, "torque")
    big = max(-lo, hi)
    if big <= 2.0 * np.sqrt(dna.bending_rigidity * _extreme(force, np.min)):
        return []  # no torque reaches the smallest force's Euler limit: skip the full mask
    for start in range(0, force.size, _BLOCK):  # masks of bounded size
        sl = slice(start, start + _BLOCK)
        limit = 2.0 * np.sqrt(dna.bending_rigidity * force[sl])
        over = (points.phase[sl] != 2) & (np.abs(points.torque[sl]) > limit)
        if np.any(over):
            j = np.flatnonzero(over)[0]
            i = start + j
            return [f"at force {display.text(force[i], 'force')}, turns {turns[i]:.6g} the "
                    "stretched tail carries a torque "
                    f"{display.text(abs(points.torque[i]), 'torque', '.4g')} above the Euler limit "
                    f"2 sqrt(B F) = {display.text(limit[j], 'torque', '.4g')}: a straight tail is "
                    "unstable there"]
    return []


def extension_messages(force, turns, points, dna):
    """An extension longer than the contour length, or negative (never silent)."""
    z = points.extension
    if z.size == 0:
        return []
    lo, hi = _range(points, "extension")
    if lo >= 0 and hi <= dna.length * (1 + 1e-12):
        return []  # two reductions (or the kernel's) instead of the masks below
    bad = (z > dna.length * (1 + 1e-12)) | (z < 0)
    if not np.any(bad):
        return []
    i = np.flatnonzero(bad)[0]
    return [f"extension {display.text(z[i], 'length')} at force "
            f"{display.text(force[i], 'force')}, turns {turns[i]:.6g} lies outside "
            f"[0, L = {display.text(dna.length, 'length')}]: the thermal formula is not valid "
            "there (a tail of a few persistence lengths or less, or a force below the "
            "thermal expansion's range)"]


#: points per block of the checks that build masks (their temporaries stay bounded)
_BLOCK = 1 << 15


def summary_of(points):
    """The kernel's :class:`~supercoil.core.dna.interface.PointSummary` if it holds, else None.

    Only a summary whose ranges are finite is used (else the checks pass over
    the arrays and name the point).
    """
    s = getattr(points, "summary", None)
    return s if s is not None and s.finite else None


def _extreme(x, reduce):
    """``reduce(x)``; for one force broadcast over the points (stride 0) its value.

    (numpy reduces a stride-0 view element by element, as a full array.)
    """
    if x.ndim == 1 and x.size and x.strides[0] == 0:
        return x[0]
    return reduce(x)


def _range(points, name):
    """``(min, max)`` of ``points.<name>``: the kernel's summary, or two reductions."""
    s = summary_of(points)
    if s is not None:
        return getattr(s, f"{name}_min"), getattr(s, f"{name}_max")
    x = getattr(points, name)
    return x.min(), x.max()


#: largest reduced stiffness A / r0 of the hard-core plectoneme (a numerical limit: the
#: solver works in units of r0 and follows the power law of R/r0 in b to b ~ 1e34;
#: measured: its R loses its digits near b ~ 5e37 and it finds no branch above ~4e40)
MAX_REDUCED_STIFFNESS = 1e30


def check_hard_core_radius(dna, radius=None):
    """ValidityError naming the hard-core radius if ``A / r0`` is beyond the solvable range.

    The hard-core plectoneme is solved in units of r0 (``b = B/(kT r0) = A/r0``,
    docs/theory/plectoneme.md); a radius of 1e-300 nm underflowed ``kT r0`` to 0
    (ZeroDivisionError). ``radius`` (m) defaults to the DNA's own.
    """
    r0 = dna.radius if radius is None else radius
    with np.errstate(over="ignore", divide="ignore"):
        b = dna.bending_persistence / r0
    check_scale(b, lambda: f"the reduced stiffness A/r0 (hard-core radius r0 = DNA.radius = "
                f"{display.text(r0, 'length')}, "
                f"A = {display.text(dna.bending_persistence, 'length')})", hi=MAX_REDUCED_STIFFNESS,
                why="the plectoneme solver works in units of r0 and loses its precision "
                    "beyond; give a hard-core radius of the order of the DNA radius (~1 nm)")


def check_interaction(interaction, dna):
    """The interaction's own check, and the hard-core scale where it uses ``dna.radius``.

    One check for every caller that hands a DNA to an interaction (the public
    DNA functions, the fits, the simulation).
    """
    if interaction.values.get("hard_core_radius") is None:
        check_hard_core_radius(dna)
    interaction.check(dna)


class StateRecorder:
    """Wraps an interaction and keeps the plectoneme states a model asked for.

    The public layer passes it to the model instead of the interaction, so the
    shared checks (:func:`plectoneme_messages`) reuse the states the model
    computed instead of solving them again.
    """

    def __init__(self, interaction):
        self.interaction = interaction
        self.states = []

    def __getattr__(self, name):
        return getattr(self.interaction, name)

    def check(self, dna):
        """:func:`check_interaction` of the wrapped interaction."""
        check_interaction(self.interaction, dna)

    def unrecorded(self):
        """The wrapped interaction: its states are not recorded."""
        return self.interaction

    def equilibrium(self, tension, dna):
        st = self.interaction.equilibrium(tension, dna)
        self.states.append(st)
        return st

    def messages(self, dna):
        hc = self.interaction.values.get("hard_core_radius")
        out = []
        for st in self.states:
            out += plectoneme_messages(st, dna, hc)
        return out

