"""Case I, smooth surface: the uniform double helix (docs/theory/smooth.md).

Public unit wrapper over :mod:`supercoil.core.rod.smooth`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from supercoil._checks import broadcast_shape
from supercoil.core.rod import contact as _sc
from supercoil.core.rod import smooth as _sm
from supercoil.rod.material import check_rod
from supercoil.rod.validity import check_finite, warn_hard_contact
from supercoil.tables import make_table, provenance
from supercoil.units import U, as_turns, magnitude, quantity

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


@dataclasses.dataclass(frozen=True)
class SmoothHelix:
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

    turns: object
    slack: object
    alpha: object
    pitch: object
    omega: object
    curvature: object
    torsion: object
    tension: object
    torque: object
    normal_force: object
    twist: object
    writhe: object
    linking_number: object
    superhelical_turns: object
    provenance: dict = dataclasses.field(repr=False, compare=False, default_factory=dict)

    def to_table(self):
        """The solution as a flat table (one row per (N, S) pair) in the package convention."""
        units = {"turns": "turn", "slack": "mm", "alpha": "rad", "pitch": "mm", "omega": "1/mm",
                 "curvature": "1/mm", "torsion": "1/mm", "tension": "N", "torque": "N*mm",
                 "normal_force": "N/m", "twist": "turn", "writhe": "turn", "linking_number": "turn",
                 "superhelical_turns": "turn"}
        cols = {k: np.ravel(getattr(self, k).magnitude) for k in units}
        return make_table(cols, units, self.provenance)


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

    def q(x, unit, scale=1.0):
        x = np.asarray(x, float) * scale
        return quantity(float(x) if x.ndim == 0 else x, unit)

    with np.errstate(over="ignore"):
        check_finite({"pitch [mm]": st["pitch"] * 1e3, "omega [1/mm]": st["omega"],
                              "tension [N]": st["tension"], "torque [N mm]": st["torque"] * 1e3,
                              "normal_force [N/m]": st["normal_force"]},
                             f"turns up to {float(np.max(np.abs(n_b), initial=0)):.6g}")
    warn_hard_contact(st["alpha"], "smooth helix")
    return SmoothHelix(
        turns=q(n_b, U.turn),
        slack=q(S_b, U.mm, 1e3),
        alpha=q(st["alpha"], U.rad),
        pitch=q(st["pitch"], U.mm, 1e3),
        omega=q(st["omega"], U.per_mm, 1e-3),
        curvature=q(st["curvature"], U.per_mm, 1e-3),
        torsion=q(st["torsion"], U.per_mm, 1e-3),
        tension=q(st["tension"], U.N),
        torque=q(st["torque"], U.N_mm, 1e3),
        normal_force=q(st["normal_force"], U.N_per_m),
        twist=q(st["twist"], U.turn),
        writhe=q(st["writhe"], U.turn),
        linking_number=q(st["linking_number"], U.turn),
        superhelical_turns=q(st["superhelical_turns"], U.turn),
        provenance=provenance(rod, scene="smooth_helix"),
    )
