"""Screened (Debye-Hueckel) interaction of the two strands of a plectoneme.
Float-only SI kernel (docs/theory/screened-interaction.md, sections 2 to 4).

Geometry
--------
Strand 1 is ``(R cos t, R sin t, p t)``, strand 2 ``(-R cos t, -R sin t, p t)`` with
``p = R cot(alpha) = P / (2 pi)``. The distance from a point of strand 1 to the point
of strand 2 at axial offset z is, with ``q = z / p``::

    d(z)^2 = z^2 + 2 R^2 (1 + cos q)

(``d = 2R`` at z = 0, ``d = |z|`` at the pitch neighbour ``q = pi``). Arclength on
strand 2 is ``ds' = dz / cos(alpha)``.

Electrostatic energy per unit DNA length
----------------------------------------
Two line charges nu (charges per length) interacting by the Debye-Hueckel pair energy
``kT l_B exp(-r/lambda)/r``. A piece ds of strand 1 interacts with the whole of strand
2; its partner piece of strand 2 does the same, and the two pieces are 2 ds of DNA, so
per unit DNA length (equal to the package's ``w`` "per strand length", since the energy
[Eq Ep1] counts ``2 w`` per length of each of the two strands of length S/2)::

    w_el(alpha, R) = (nu^2 kT l_B / (2 cos alpha)) int_{-inf}^{inf} exp(-d/lambda)/d dz.

Limit alpha -> 0 (p -> inf, d -> sqrt(z^2 + 4R^2)): ``w_el -> nu^2 kT l_B K0(2R/lambda)``,
two parallel line charges at distance 2R (tested). The integral is done with a fixed
Gauss-Legendre rule in t for ``z = 2R sinh t`` (``dz = d0 dt``, ``d0 = 2R cosh t``), on
``0 <= t <= t_max`` with ``cosh t_max = 1 + 40 lambda/(2R)`` (the integrand is below
e^-40 of its peak beyond); against adaptive quadrature (scipy quad, rtol 1e-13) the error
is below 1e-11 relative for alpha = 2-40 deg, R = 1-10 nm, lambda = 0.3-3 nm, below 1e-10 up
to 45 deg (the solver never goes beyond 45 deg) and 6e-9 at 60 deg. The partials are the
same rule applied to the analytic z-derivatives of the integrand at fixed z:

    d(d^2)/dR     = 4R (1 + cos q) + 2R q sin q,
    d(d^2)/dalpha = -4 R^2 q sin q / sin(2 alpha),
    d/dd [exp(-d/lambda)/d] = -exp(-d/lambda) (1/(lambda d) + 1/d^2).

Entropic confinement (the paper's Marko-Siggia form, Li, Zhao et al., Example III;
docs/theory/plectoneme.md)::

    w_conf = kT A^(-1/3) [R^(-2/3) + (pi R cot alpha)^(-2/3)],   A = B/kT.

Hard core: the strands are cylinders of radius ``a``; they pass through each other
once their closest approach ``d_min`` falls below 2a. For alpha <= pi/4,
``d_min = 2R`` (``d(z)^2 - 4R^2 = z^2 - 2R^2(1 - cos q) >= z^2 (1 - tan^2 alpha) >= 0``),
so the constraint is ``R > a``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "CUTOFF_DECAYS",
    "QUADRATURE_NODES",
    "closest_approach",
    "confinement",
    "confinement_partials",
    "electrostatic",
    "electrostatic_partials",
    "parallel_rods",
]

#: integrand cut where exp(-(d - 2R)/lambda) < exp(-CUTOFF_DECAYS)
CUTOFF_DECAYS = 40.0
#: Gauss-Legendre nodes of the fixed rule in t (z = 2R sinh t)
QUADRATURE_NODES = 96
_X, _W = np.polynomial.legendre.leggauss(QUADRATURE_NODES)
_X = 0.5 * (_X + 1.0)
_W = 0.5 * _W


def parallel_rods(radius, debye, prefactor):
    """``prefactor K0(2R/lambda)``: two parallel line charges at distance 2R (J/m).

    ``prefactor = nu^2 kT l_B`` (J/m).

    Implements docs/theory/screened-interaction.md (SI5).
    """
    from scipy.special import k0

    return prefactor * k0(2.0 * np.asarray(radius, float) / debye)


def _nodes(alpha, radius, debye):
    """Quadrature nodes z (m) and weights dz (m), shape (..., n), half line z >= 0.

    ``sinh t`` and ``cosh t`` from one ``exp`` (a third of the cost of numpy's sinh and
    cosh); at the smallest node ``t ~ 1e-4`` the difference ``(e^t - e^-t)/2`` keeps
    about 12 digits of z, where z enters d only as ``z^2`` against ``4 R^2``.
    """
    alpha, radius = np.broadcast_arrays(np.asarray(alpha, float), np.asarray(radius, float))
    half = radius[..., None]  # D / 2, D = 2R
    t_max = np.arccosh(1.0 + CUTOFF_DECAYS * debye / (2.0 * half))
    e = np.exp(t_max * _X)
    inv = 1.0 / e
    z = e - inv
    z *= half  # D sinh t
    dz = e + inv
    dz *= half * t_max
    dz *= _W  # D cosh t t_max w
    return alpha, radius, z, dz


def _distance(alpha, radius, z):
    """``(d, q, R, 1 + cos q)`` at the nodes z."""
    p = (radius * np.cos(alpha) / np.sin(alpha))[..., None]
    q = z / p
    R = radius[..., None]
    c1 = np.cos(q)
    c1 += 1.0
    d = c1 * (2.0 * R * R)
    d += z * z
    return np.sqrt(d, out=d), q, R, c1


def electrostatic(alpha, radius, debye, prefactor):
    """Screened interaction ``w_el(alpha, R)`` per unit DNA length (J/m).

    Parameters
    ----------
    alpha : float or array
        Tilt (rad), ``0 < alpha < pi/2``.
    radius : float or array
        Superhelix radius R (m).
    debye : float
        Debye length lambda_D (m).
    prefactor : float
        ``nu^2 kT l_B`` (J/m): squared effective line charge (1/m^2) times kT (J) times
        the Bjerrum length (m).

    Notes
    -----
    Implements docs/theory/screened-interaction.md (SI4).
    """
    alpha, radius, z, dz = _nodes(alpha, radius, debye)
    d = _distance(alpha, radius, z)[0]
    integral = 2.0 * np.sum(np.exp(d / -debye) / d * dz, axis=-1)
    return prefactor * integral / (2.0 * np.cos(alpha))


def electrostatic_partials(alpha, radius, debye, prefactor):
    """``(w_el, dw_el/dalpha, dw_el/dR)`` in (J/m, J/m, J/m^2).

    Implements docs/theory/screened-interaction.md (SI4).
    """
    alpha, radius, z, dz = _nodes(alpha, radius, debye)
    d, q, R, c1 = _distance(alpha, radius, z)
    inv_d = 1.0 / d
    e = np.exp(d / -debye)
    e *= inv_d
    # d/dd [exp(-d/lambda)/d] = -e (1/lambda + 1/d), times dd = d(d^2) / (2d); the
    # constant 1/sin(2 alpha) of d(d^2)/dalpha taken out of the sum (in place: no new
    # (points, nodes) array per product)
    g = inv_d + 1.0 / debye
    g *= e
    inv_d *= 0.5
    g *= inv_d
    g *= dz
    q_sin_q = np.sin(q)
    q_sin_q *= q
    e *= dz
    I = 2.0 * np.sum(e, axis=-1)
    c1 *= 4.0 * R  # 4R (1 + cos q) + 2R q sin q
    c1 += q_sin_q * (2.0 * R)
    c1 *= g
    I_R = -2.0 * np.sum(c1, axis=-1)
    g *= q_sin_q
    I_a = 2.0 * np.sum(g, axis=-1) * (4.0 * radius * radius) / np.sin(2.0 * alpha)
    c = np.cos(alpha)
    k = prefactor / (2.0 * c)
    w = k * I
    w_a = k * (I_a + I * np.tan(alpha))
    w_R = k * I_R
    return w, w_a, w_R


def confinement(alpha, radius, B, kT):
    """Entropic confinement ``kT A^(-1/3) [R^(-2/3) + (pi R cot alpha)^(-2/3)]`` (J/m).

    Implements docs/theory/screened-interaction.md (SI6).
    """
    k = kT * (B / kT) ** (-1.0 / 3.0)
    R = np.asarray(radius, float)
    half_pitch = np.pi * R / np.tan(alpha)
    return k * (R ** (-2.0 / 3.0) + half_pitch ** (-2.0 / 3.0))


def confinement_partials(alpha, radius, B, kT):
    """``(w_conf, dw_conf/dalpha, dw_conf/dR)`` of :func:`confinement`.

    Implements docs/theory/screened-interaction.md (SI6).
    """
    k = kT * (B / kT) ** (-1.0 / 3.0)
    R = np.asarray(radius, float)
    tan = np.tan(alpha)
    h = np.pi * R / tan
    h23 = h ** (-2.0 / 3.0)
    r23 = R ** (-2.0 / 3.0)
    w = k * (r23 + h23)
    # dh/dalpha = -pi R (1 + tan^2) / tan^2 ;  dh/dR = h / R
    w_a = k * (-2.0 / 3.0) * h23 / h * (-np.pi * R * (1.0 + tan * tan) / (tan * tan))
    w_R = k * (-2.0 / 3.0) * (r23 + h23) / R
    return w, w_a, w_R


def closest_approach(alpha, radius, samples=2048):
    """Closest distance between the two strand axes, ``min_z d(z)`` (m).

    ``2R`` for ``alpha <= pi/4`` (module docstring); above that it is found on a grid
    of ``samples`` points over one pitch (used only to report where the strands meet).
    """
    alpha, radius = np.broadcast_arrays(np.asarray(alpha, float), np.asarray(radius, float))
    p = radius * np.cos(alpha) / np.sin(alpha)
    q = np.linspace(0.0, 2.0 * np.pi, samples)
    z = p[..., None] * q
    d = np.sqrt(z * z + 2.0 * radius[..., None] ** 2 * (1.0 + np.cos(q)))
    return np.minimum(np.min(d, axis=-1), 2.0 * radius)
