"""Hard-contact double helix (R = r): formulas shared by the smooth and rough rods.

Float-only kernel (SI units: m, N, N m^2, rad); everything broadcasts; no pint.
docs/theory/contact.md, paper [eq dom/ds1 self contact, eq ini, eq tension,
eq normal reaction, eq friction].

Notation: ``c = cos 2 alpha``, ``y = 1 - cos 2 alpha = 2 sin^2 alpha`` (the
variable the rough-helix ODE is integrated in: it is regular where alpha -> 0,
see :mod:`supercoil.core.rod.rough`), ``B`` bending and ``C`` torsional
rigidity, ``r`` the rod radius (= helix radius R in hard contact).

Hard contact (w = 0 for R > r, infinite for R < r) gives, from (GE1),

    (HC)  omega = (B/C) (1 - cos 2a) tan 2a / (2 r)          [eq dom/ds1 self contact]

which needs ``0 <= alpha < pi/4``: at alpha -> pi/4 omega, the tension and the
normal force diverge like ``1 / cos 2 alpha`` (:func:`check_tilt` turns that
into a :class:`~supercoil.exceptions.SingularityError`).

Normal force: a factor 2 in [eq normal reaction]
-------------------------------------------------
The contact force per unit length of strand is ``F = -de/dR`` with e the
elastic energy per unit rod length at fixed linking number (each strand moves
by dR, so the virtual work of the contact forces on a piece of total rod
length l is ``F l dR``). Appendix D computes exactly this derivative,
``d delta E = -[B (1 - c)^2 / (4 R^3 c)] delta S dR``, and then divides by 2 by
differentiating with respect to the diameter D = 2R instead; that step
mixes the relative displacement of the pair with the displacement of one
strand. Two independent checks give the undivided value:

* Kirchhoff rod, uniform helix, free head (zero axial force and torque through
  a cut): the moment balance gives ``n_b = kappa (C omega - B tau)``, zero
  axial force gives ``n_t = -n_b tan(a)``, the axial torque balance reproduces
  (HC), and the force balance along the principal normal gives
  ``F = n_t kappa - n_b tau = B sin^4(a) / (R^3 cos 2a)``;
* Lagrange multiplier of the constraint R >= r in the smooth-helix energy:
  ``F = (1/S) dE_p/dR`` at fixed N, S and alpha (stationary in alpha), tested
  in ``tests/test_smooth_helix.py``.

So :func:`normal_force` returns

    F = B (1 - cos 2a)^2 / (4 r^3 cos 2a) = B sin^4(a) / (r^3 cos 2a)     [N/m]

(twice the paper's printed value; :func:`normal_force_paper`
keeps the printed formula for comparison).

Dimensional fix of [eq friction]
--------------------------------
The paper writes the available friction torque per length as
``dM_fmax/ds = B mu cos(a) (1 - cos 2a)^2 / (8 R^3 cos 2a)``. That has the unit
N/m, while the left side of the no-slip condition [eq friction con],
``C |d omega/ds|``, is a torque per length, N m / m = N. From [eq dM_f],
``dM_f = cos(a) R f ds`` with ``f_max = mu F``, the consistent expression is

    dM_fmax/ds = mu R cos(a) F = B mu cos(a) (1 - cos 2a)^2 / (4 R^2 cos 2a)   [N]

which is what :func:`friction_torque_available` returns (one power of R less
than printed, and the factor 2 of F above). Evaluated in SI units the printed
formula is 1/(2 r) = 500 /m times larger for r = 1 mm, which is why the paper
finds slip only "extremely close to s_max".
"""

from __future__ import annotations

import numpy as np

from supercoil.core.numerics import bisect_increasing
from supercoil.exceptions import NoHelixError, SingularityError

__all__ = ["bisect_increasing"]  # re-exported from supercoil.core.numerics (old home)

TWO_PI = 2.0 * np.pi
QUARTER_PI = 0.25 * np.pi

#: Default singularity guard: ``cos 2 alpha`` below this counts as alpha -> pi/4
#: (tension, normal force and twist density ~ 1/cos 2 alpha diverge).
COS2A_MIN = 1e-9


#: Validity limit of hard contact (R = r): the Hertz contact half-width b of the two
#: strands may not exceed the rod radius, ``b / r <= 1`` (see :func:`contact_width_ratio`).
CONTACT_WIDTH_MAX = 1.0


def contact_width_ratio(alpha):
    """Hertz half-width of the strand-strand contact over the rod radius, ``b / r``.

    The hard-contact model (R = r) treats the cross-section as rigid against
    the contact force per length ``F = B sin^4(a) / (r^3 cos 2a)``. Two parallel
    elastic cylinders of radius r pressed together by F per length touch over a
    strip of half-width (Hertz line contact, reduced radius r/2, contact modulus
    ``E* = E / (2 (1 - nu^2))``)

        b^2 = 4 F (r/2) / (pi E*) = 4 (1 - nu^2) F r / (pi E),

    and with ``B = pi E r^4 / 4`` (solid circular rod)

        b / r = sqrt(1 - nu^2) sin^2(a) / sqrt(cos 2a)  <=  sin^2(a) / sqrt(cos 2a),

    independent of E and r; this returns the bound (nu = 0; for rubber,
    nu ~ 0.4-0.5, b is 13-15 % smaller). Hertz theory, and R = r with it,
    needs ``b << r``: at ``b = r`` (:data:`CONTACT_WIDTH_MAX`), i.e.
    ``sin^4 a = cos 2a``, ``cos 2a = 3 - 2 sqrt 2 = 0.172``, alpha = 0.699 rad
    (40.1 deg), the contact would flatten the strand across its whole diameter
    and the model has certainly failed. There the bending strain is
    ``r kappa = sin^2 a = sqrt 2 - 1 = 0.41`` and the surface shear strain of
    the twist ``r omega = (B/C) (1 - c) tan(2a) / 2 = 2.38 B/C`` (3.3 for
    silicone rubber, B/C = E/(2G) = 1.39). The paper's own rods already reach
    ``r omega = 2 pi N r / L = 0.44`` (r = 1 mm, L = 56.7 cm, N = 40; b/r = 0.29)
    and 1.13 (r = 1.7 mm, L = 142 cm, N = 150; b/r = 0.53) at the head, so a
    small-strain limit such as r omega < 0.1 would flag every experiment the
    model is meant to describe; the contact width is the assumption that
    diverges with the tension at alpha -> pi/4.
    """
    a = np.asarray(alpha, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.sin(a) ** 2 / np.sqrt(np.cos(2.0 * a))


def contact_warning(alpha, where):
    """Message for a ValidityWarning if some ``b / r > CONTACT_WIDTH_MAX``, else None."""
    a = np.asarray(alpha, float)
    if a.size == 0:
        return None
    lo, hi = float(np.min(a)), float(np.max(a))
    if 0.0 <= lo and contact_width_ratio(hi) <= CONTACT_WIDTH_MAX * (1.0 - 1e-12):
        # b / r increases with alpha on [0, pi/4): below the limit at the largest tilt
        # (with a margin far above the rounding) it is below it everywhere
        return None
    ratio = contact_width_ratio(a)
    worst = float(np.max(ratio))
    if not worst > CONTACT_WIDTH_MAX:
        return None
    a_w = float(a.reshape(-1)[int(np.argmax(ratio))])
    return (f"tilt alpha = {a_w:.6g} rad ({where}): the Hertz contact half-width of the "
            f"strands b = {worst:.3g} r exceeds the limit b = {CONTACT_WIDTH_MAX:g} r "
            f"(alpha > 0.699 rad, cos 2 alpha < 0.172): hard contact R = r has failed and "
            "tension, torque and normal force (~ 1/cos 2 alpha) are not trustworthy")


def check_cos2a_min(cos2a_min):
    """Return ``cos2a_min`` as a float after checking ``0 < cos2a_min < 1``.

    Raises
    ------
    ValueError
        If it is NaN or outside (0, 1): 0 or less never fires (the tension is
        returned up to infinity), 1 or more rejects every tilt.
    """
    try:
        c = float(cos2a_min)
    except (TypeError, ValueError):
        raise TypeError(f"cos2a_min must be a number in (0, 1), got {cos2a_min!r}") from None
    if not 0.0 < c < 1.0:
        raise ValueError(f"cos2a_min must lie in (0, 1) (the alpha -> pi/4 guard on "
                         f"cos 2 alpha), got {cos2a_min!r}")
    return c


def check_scalar(value, name, lo=-np.inf, hi=np.inf, lo_open=True, hi_open=True, what=""):
    """Return ``value`` as a finite float after checking it lies in the interval (lo, hi).

    ``lo_open``/``hi_open`` choose open or closed ends; the message names the
    argument, the interval and ``what`` (why the limit exists).

    Raises
    ------
    TypeError
        If ``value`` is not a real number.
    ValueError
        If it is NaN, infinite or outside the interval.
    """
    if isinstance(value, bool | str | bytes) or value is None:
        raise TypeError(f"{name} must be a number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a number, got {value!r}") from None
    below = x <= lo if lo_open else x < lo
    above = x >= hi if hi_open else x > hi
    if not np.isfinite(x) or below or above:
        interval = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
        raise ValueError(f"{name} must be finite and lie in {interval}{what}, got {value!r}")
    return x


# --- variables -------------------------------------------------------------


def y_of_alpha(alpha):
    """``y = 1 - cos 2 alpha = 2 sin^2 alpha`` (accurate for small alpha)."""
    return 2.0 * np.sin(alpha) ** 2


def alpha_of_y(y):
    """Inverse of :func:`y_of_alpha`: ``alpha = arcsin(sqrt(y / 2))``."""
    return np.arcsin(np.sqrt(np.clip(np.asarray(y, float), 0.0, 1.0) / 2.0))


def g_contact(alpha):
    """``g(alpha) = (1 - cos 2a) tan 2a``, the left side of [eq ini] (dimensionless).

    Increases monotonically from 0 at alpha = 0 to infinity at pi/4.
    """
    return y_of_alpha(alpha) * np.tan(2.0 * alpha)


# --- hard-contact relations -------------------------------------------------


def twist_density(alpha, r, B, C):
    """(HC) ``omega = (B/C) (1 - cos 2a) tan 2a / (2 r)`` in rad/m [eq dom/ds1 self contact].

    Implements docs/theory/contact.md (HC).
    """
    return (B / C) * g_contact(alpha) / (2.0 * r)


def dtwist_dalpha(alpha, r, B, C):
    """``d omega / d alpha = (B / (C r)) [sin^2 2a / cos 2a + (1 - cos 2a) / cos^2 2a]`` (1/m)."""
    c = np.cos(2.0 * alpha)
    return (B / (C * r)) * (np.sin(2.0 * alpha) ** 2 / c + y_of_alpha(alpha) / c**2)


def initial_tilt(turns_abs, r, L, B, C):
    """alpha_0 of [eq ini]: ``(1 - cos 2a0) tan 2a0 = (C/B) 4 pi r |N_0| / L``.

    Implements docs/theory/contact.md (eq ini).

    This is (HC) with the uniform twist ``omega = 2 pi N_0 / L`` of the straight
    rod at S = 0. Solved by vectorised bisection
    (:func:`supercoil.core.numerics.bisect_increasing`) in ``(0, pi/4)`` on the
    regular form ``(1 - c) sin 2a - rhs c = 0`` (increasing in alpha).

    Raises
    ------
    NoHelixError
        If some ``|N_0| <= 0`` (alpha_0 = 0: no twist, no helix).
    """
    n = np.asarray(turns_abs, float)
    if np.any(~(n > 0)):
        raise NoHelixError(
            "turns N_0 = 0 before slacking: alpha_0 = 0 by [eq ini], the pitch is "
            "infinite and no double helix forms (need |N_0| > 0)"
        )
    rhs = (C / B) * 4.0 * np.pi * r * n / L

    def h(a):
        return y_of_alpha(a) * np.sin(2.0 * a) - rhs * np.cos(2.0 * a)

    return bisect_increasing(h, np.zeros_like(rhs), np.full_like(rhs, QUARTER_PI))


def tension(alpha, r, B):
    """[eq tension] ``T = B/(8 r^2) (1 - c)^2 (2 + c) / c`` (N), c = cos 2 alpha.

    Implements docs/theory/contact.md (eq tension).

    The same expression is the smooth-surface tension ``C omega tau - B kappa^2/2``
    with (HC) inserted (:func:`smooth_tension`), i.e. the tension depends only
    on the tilt at the helix end.
    """
    c = np.cos(2.0 * alpha)
    y = y_of_alpha(alpha)
    return B / (8.0 * r**2) * y**2 * (2.0 + c) / c


def smooth_tension(alpha, omega, r, B, C):
    """``T = -dE_p/dS|_N = C omega tau - B kappa^2 / 2`` (N), docs/theory/smooth.md with w = 0."""
    sa, ca = np.sin(alpha), np.cos(alpha)
    return C * omega * sa * ca / r - 0.5 * B * sa**4 / r**2


def normal_force(alpha, r, B):
    """Contact force per strand length ``F = B/(4 r^3) (1 - c)^2 / c`` (N/m), c = cos 2a.

    Implements docs/theory/contact.md (eq normal reaction).

    [eq normal reaction] corrected by the factor 2 derived in the module
    docstring (the paper prints ``B/(8 R^3)``, see :func:`normal_force_paper`).
    """
    c = np.cos(2.0 * alpha)
    return B / (4.0 * r**3) * y_of_alpha(alpha) ** 2 / c


def normal_force_paper(alpha, r, B):
    """[eq normal reaction] as printed, ``B/(8 R^3) (1 - c)^2 / c`` (N/m); half of F.

    Implements docs/theory/contact.md (eq normal reaction).
    """
    return 0.5 * normal_force(alpha, r, B)


def friction_torque_available(alpha, r, B, mu):
    """Available friction torque per length ``dM_fmax/ds = mu r cos(a) F`` (N).

    Implements docs/theory/contact.md (eq friction con, eq dM_f).

    [eq friction] with the two fixes described in the module docstring:
    ``B mu cos(a) (1 - cos 2a)^2 / (4 r^2 cos 2a)``.
    """
    return mu * r * np.cos(alpha) * normal_force(alpha, r, B)


def friction_torque_required_y(y, dy_ds, r, B):
    """Required friction torque per length ``C |d omega/ds|`` (N), from ``y`` and ``dy/ds``.

    ``C d omega/ds = C (d omega/d alpha) (d alpha/ds)`` with ``d alpha/ds =
    (dy/ds) / (2 sin 2a)``; written as
    ``(B / (2 r)) [sin 2a / c + sqrt(y / (2 - y)) / c^2] dy/ds``, which stays
    finite (-> 0) at alpha -> 0 where d alpha/ds diverges.
    """
    y = np.asarray(y, float)
    c = 1.0 - y
    s2 = np.sqrt(np.clip(y * (2.0 - y), 0.0, None))
    bracket = s2 / c + np.sqrt(np.clip(y, 0.0, None) / (2.0 - y)) / c**2
    return np.abs(B / (2.0 * r) * bracket * np.asarray(dy_ds, float))


def check_tilt(alpha, where, cos2a_min=COS2A_MIN):
    """Raise if some tilt reaches the pi/4 singularity or leaves ``[0, pi/4)``.

    Raises
    ------
    SingularityError
        If ``cos 2 alpha < cos2a_min`` (alpha -> pi/4: tension, normal force and
        twist density diverge like ``1 / cos 2 alpha``); the message names
        ``where`` (the inputs that led there).
    """
    a = np.asarray(alpha, float)
    if a.size:
        lo, hi = float(np.min(a)), float(np.max(a))  # NaN reaches both
        m = max(-lo, hi)
        if m < 0.25 * np.pi and np.cos(2.0 * m) >= cos2a_min + 1e-12:
            # cos 2 alpha decreases with |alpha| up to pi/4: above the limit at the
            # largest |alpha| (with a margin far above the rounding), above it everywhere
            return a
    if not np.all(np.isfinite(a)):
        raise SingularityError(f"tilt alpha is not finite ({where})")
    c = np.cos(2.0 * a)
    bad = c < cos2a_min
    if np.any(bad):
        worst = float(np.max(a[bad])) if a.ndim else float(a)
        raise SingularityError(
            f"tilt alpha = {worst:.12g} rad reaches the limit alpha -> pi/4 "
            f"(cos 2 alpha = {np.cos(2 * worst):.3g} < {cos2a_min:g}): tension "
            f"~ B / (4 r^2 cos 2 alpha) diverges ({where})"
        )
    return a
