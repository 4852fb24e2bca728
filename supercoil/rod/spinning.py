"""Twist-spinning comparison: beta and pitch versus head tension T' (docs/theory/spinning.md).

Public unit wrapper over :mod:`supercoil.core.rod.spinning`, whose module
docstring holds the derivation of the stationarity equations [f4, f5] from
the stated energy, what is held fixed, and the T' = 0 limit.
"""

from __future__ import annotations

import numpy as np

from supercoil._checks import broadcast_shape
from supercoil.core.rod import contact as _sc
from supercoil.core.rod import spinning as _ts
from supercoil.records import Record, si_value
from supercoil.rod.material import check_rod
from supercoil.rod.smooth import checked_turns
from supercoil.rod.validity import check_finite_scaled, warn_hard_contact
from supercoil.tables import provenance
from supercoil.units import U, magnitude

__all__ = ["TwistSpinningHelix", "twist_spinning"]


class TwistSpinningHelix(Record):
    """Short smooth helix under a head tension (result of :func:`twist_spinning`).

    All attributes are quantities broadcast over turns and head_tension.

    Attributes
    ----------
    turns : Quantity [turn]
        N (signed).
    head_tension : [N]
        T'.
    alpha : [rad]
        Tilt, root of [f4].
    beta : [rad]
        Half-angle between the tails (angle of a tail to the helix axis), from
        [f5]; pi/2 at T' = 0.
    pitch : [mm]
        ``2 pi r / tan(alpha)``.
    omega : [1/mm]
        Twist density ``2 pi N / L`` (S'/L -> 0), signed like N.
    alpha_slacking, pitch_slacking : [rad], [mm]
        The twist-slacking helix at the same N (T' = 0, [eq ini]).
    pitch_increase : dimensionless
        ``pitch / pitch_slacking - 1``: the deviation twist-spinning leaves
        behind once T' is released.
    """

    __slots__ = ()
    DOMAIN = "rod"
    FIELDS = ("turns", "head_tension", "alpha", "beta", "pitch", "omega", "alpha_slacking",
              "pitch_slacking", "pitch_increase")
    EXTRA = ("provenance",)


def twist_spinning(rod, turns, head_tension):
    """beta and pitch of a twist-spun helix versus head tension T'.

    The model of the paper's Discussion (docs/theory/spinning.md): a smooth rod of length
    L twisted by N turns, ends held apart, a short helix (S' << L) at the head
    pulled by T' along its axis. Stationarity of
    ``E_p = (1/2) B kappa^2 S' + (1/2) C omega^2 L - T' h`` in alpha and S' at
    fixed L, N, S and T' gives [f4] for alpha and [f5] for beta (derivation in
    :mod:`supercoil.core.rod.spinning`; the helix height is
    ``(S'/2) cos(alpha)``, not the ``S'/cos(alpha)`` printed in [f1]).
    T' = 0 gives beta = pi/2 and the twist-slacking tilt of [eq ini].

    Parameters
    ----------
    rod : ElasticRod
    turns : number, array or dimensionless/angle Quantity
        N (sign: handedness; omega carries it).
    head_tension : Quantity [force], scalar or array
        T' >= 0. Broadcasts with turns.

    Returns
    -------
    TwistSpinningHelix

    Raises
    ------
    NoHelixError
        N = 0 or T' < 0 (or NaN/inf). No T' closes the tails: sec(beta) >= 1
        holds for every solution (proof in :mod:`supercoil.core.rod.spinning`).
    SingularityError
        alpha within ``cos 2 alpha < 1e-9`` of pi/4.
    ValueError
        turns NaN or infinite ("turns must be finite").
    TypeError
        turns None or text.

    Warns
    -----
    ValidityWarning
        Hard contact fails: Hertz contact half-width above the rod radius
        (alpha > 0.699 rad, see :func:`supercoil.core.rod.contact.contact_width_ratio`).
    """
    si = check_rod(rod)
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    n = np.asarray(checked_turns(turns, "turns"), float)
    Tp = np.asarray(magnitude(head_tension, U.N, "head_tension"), float)
    broadcast_shape(turns=n, head_tension=Tp)
    st = _ts.spinning_scene(n, Tp, r, L, B, C)
    _sc.check_tilt(st["alpha"], "twist-spinning helix")
    shape = st["alpha"].shape
    a0, p0, increase = st["alpha_slacking"], st["pitch_slacking"], st["pitch_increase"]
    check_finite_scaled({"pitch [mm]": (st["pitch"], 1e3), "pitch_slacking [mm]": (p0, 1e3),
                         "pitch_increase": (increase, 1.0)},
                        "twist_spinning: tiny |N| or huge head_tension")

    warn_hard_contact(st["alpha"], "twist-spinning helix")
    return TwistSpinningHelix(
        turns=si_value(np.broadcast_to(n, shape)),
        head_tension=si_value(np.broadcast_to(Tp, shape)),
        alpha=si_value(st["alpha"]), beta=si_value(st["beta"]),
        pitch=si_value(st["pitch"]), omega=si_value(st["omega"]),
        alpha_slacking=si_value(a0), pitch_slacking=si_value(p0),
        pitch_increase=si_value(increase),
        provenance=provenance(rod, scene="twist_spinning"))

