"""Case I, smooth surface: the uniform double helix (docs/theory/smooth.md).

Public unit wrapper over :mod:`supercoil.core.rod.smooth`.
"""

from __future__ import annotations

import numpy as np

from supercoil._checks import broadcast_shape
from supercoil.core.rod import contact as _sc
from supercoil.core.rod import smooth as _sm
from supercoil.records import Record, si_value
from supercoil.rod.material import check_rod
from supercoil.rod.validity import check_finite, warn_hard_contact
from supercoil.tables import provenance
from supercoil.units import U, as_turns, magnitude

__all__ = ["SmoothHelix", "smooth_helix"]

#: Old name of :func:`supercoil.rod.validity.check_finite` (kept for importers).
check_finite_results = check_finite


def checked_turns(turns, name="turns"):
    """Turns N as float(s) (:func:`~supercoil.units.as_turns`), refusing None, NaN and inf.

    Raises
    ------
    TypeError
        If ``turns`` is None or not numeric (as_turns would read None as NaN).
    ValueError
        If some value is NaN or infinite ("turns must be finite").
    """
    if turns is None:
        raise TypeError(f"{name} must be a number, an array of numbers or a dimensionless/"
                        "angle quantity, got None")
    n = as_turns(turns, name)
    a = np.asarray(n, float)
    if not np.all(np.isfinite(a)):
        bad = a[~np.isfinite(a)].reshape(-1)[0]
        raise ValueError(f"{name} must be finite, got {float(bad)!r}")
    return n


class SmoothHelix(Record):
    """The uniform hard-contact helix of a smooth rod at turns N and slack S.

    All fields are quantities broadcast to the common shape of (turns, slack).

    Attributes
    ----------
    turns, slack : Quantity [turn], [mm]
        The inputs N (signed) and S.
    alpha : Quantity [rad]
        Tilt angle (uniform).
    pitch : Quantity [mm]
        ``P = 2 pi r / tan(alpha)``.
    omega : Quantity [1/mm]
        Twist density, uniform over helix and tail, signed like N.
    tension : Quantity [N]
        ``T = C omega tau - B kappa^2 / 2 = -dE_p/dS`` at fixed N.
    torque : Quantity [N mm]
        Twist moment ``M_3 = C omega`` (signed like N).
    normal_force : Quantity [N/m]
        Contact force per strand length, ``B (1 - cos 2a)^2 / (4 r^3 cos 2a)``
        ([eq normal reaction] corrected by a factor 2, see
        :mod:`supercoil.core.rod.contact`).
    twist, writhe, linking_number : Quantity [turn]
        Counts of turns (pint ``turn``: ``.m`` is the count; do not convert them
        with ``.to("dimensionless")``, which multiplies by 2 pi).
        ``Tw = omega L / 2 pi``, ``Wr = tau S / 2 pi``, ``Lk = Tw + Wr = N``
        [Eq Lk=Tw+Wr], signed like N (a negative N mirrors the helix).
    superhelical_turns : Quantity [turn]
        ``n = S sin(alpha) / (4 pi r)``, signed like N and the writhe, so that
        ``Wr = 2 cos(alpha) n`` holds with signs (its magnitude counts the
        turns of the superhelix; :func:`supercoil.geometry.superhelical_turns`
        returns that unsigned magnitude).
    """

    __slots__ = ()
    DOMAIN = "rod"
    FIELDS = ("turns", "slack", "alpha", "pitch", "omega", "curvature", "torsion", "tension",
              "torque", "normal_force", "twist", "writhe", "linking_number",
              "superhelical_turns")
    EXTRA = ("provenance",)


def smooth_helix(rod, turns, slack, *, cos2a_min=_sc.COS2A_MIN):
    """Uniform double helix of a smooth (frictionless) rod at turns N and slack S.

    Solves the linking balance [smooth surface] ``omega = (2 pi N - tau S) / L``
    together with hard contact (HC) ``omega = (B/C)(1 - cos 2a) tan 2a / (2 r)``
    (R = r) for the tilt alpha. Without friction the state depends only on
    (N, S): it is independent of the twisting and slacking history.

    Parameters
    ----------
    rod : ElasticRod
    turns : number, array or dimensionless/angle Quantity
        Linking number N (plain numbers count turns). Sign gives the handedness:
        the package works with |N| and attaches sign(N) to omega, torque, twist
        and writhe (negative N mirrors the helix).
    slack : Quantity [length], scalar or array
        Slack S (rod length in the helix, both strands). Broadcasts with turns.
    cos2a_min : float
        Singularity guard in (0, 1): ``cos 2 alpha < cos2a_min`` counts as
        alpha -> pi/4.

    Returns
    -------
    SmoothHelix
        Empty arrays in give empty arrays out.

    Raises
    ------
    NoHelixError
        When no helix exists, naming the condition: ``S < 0`` (the ends are
        pulled apart), ``S >= L`` (no tail left), or ``N = 0`` ("too few turns
        for contact"). In the hard-contact model the contact force
        ``F = B (1 - cos 2a)^2 / (4 r^3 cos 2a)`` is positive for every
        ``0 < alpha < pi/4``, and the helix equation ``F(alpha) = (B L/(2 C r))
        (1 - cos 2a) tan 2a + S sin(a) cos(a)/r - 2 pi |N|`` increases from
        ``-2 pi |N|`` to infinity, so every ``|N| > 0`` gives exactly one helix
        in contact; only ``N = 0`` gives none (alpha = 0: a flat hairpin of
        parallel strands, infinite pitch). The model ignores the loop at the head
        and the buckling threshold (docs/theory/limits.md#not-modelled), so a small
        |N| gives a real, very loose helix here.
    SingularityError
        When alpha comes within ``cos 2 alpha < cos2a_min`` of pi/4 (large
        |N| r / L): the tension ~ B / (4 r^2 cos 2 alpha) diverges.
    ValueError
        turns or slack NaN or infinite ("turns must be finite"), cos2a_min
        outside (0, 1).
    TypeError
        turns None or text.

    Warns
    -----
    ValidityWarning
        Where hard contact fails long before the singularity: the Hertz contact
        half-width of the strands exceeds the rod radius, ``b / r = sin^2 a /
        sqrt(cos 2a) > 1`` (alpha > 0.699 rad; derivation and strains in
        :func:`supercoil.core.rod.contact.contact_width_ratio`).
    """
    si = check_rod(rod)
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    n = checked_turns(turns, "turns")
    S = magnitude(slack, U.m, "slack")
    if not np.all(np.isfinite(S)):
        raise ValueError(f"slack must be finite, got {slack!r}")
    broadcast_shape(turns=n, slack=S)
    cos2a_min = _sc.check_cos2a_min(cos2a_min)
    with np.errstate(over="ignore", divide="ignore"):  # results checked below
        st = _sm.smooth_state(n, S, r, L, B, C, cos2a_min)
    shape = st["alpha"].shape
    n_b = np.broadcast_to(np.asarray(n, float), shape)
    S_b = np.broadcast_to(np.asarray(S, float), shape)

    n_max = max(float(np.max(n_b)), -float(np.min(n_b))) if n_b.size else 0.0
    with np.errstate(over="ignore"):
        # one field at a time: one temporary of the input's size, not five
        for name, key, scale in (("pitch [mm]", "pitch", 1e3), ("omega [1/mm]", "omega", 1.0),
                                 ("tension [N]", "tension", 1.0),
                                 ("torque [N mm]", "torque", 1e3),
                                 ("normal_force [N/m]", "normal_force", 1.0)):
            check_finite({name: st[key] * scale if scale != 1.0 else st[key]},
                         f"turns up to {n_max:.6g}")
    # the contact width grows with the tilt: the largest tilt decides the warning
    alpha = st["alpha"]
    warn_hard_contact(alpha.reshape(-1)[[int(np.argmax(alpha))]] if np.size(alpha) else alpha,
                      "smooth helix")
    fields = {k: si_value(st[k]) for k in SmoothHelix.FIELDS[2:]}
    return SmoothHelix(turns=si_value(n_b), slack=si_value(S_b), **fields,
                       provenance=provenance(rod, scene="smooth_helix"))

