"""Marko-Siggia inter-strand interaction of a DNA plectoneme. Float-only kernel.

docs/theory/plectoneme.md#interaction.

Per unit strand length, with ``x = pi cot(alpha) = P / (2 R)`` and ``r = r0``::

    w(alpha, R) = [1 + x^-12] kT/r (R/r)^-12                          (hard core)
                + B^(-1/3) [1 + x^(-2/3)] (kT)^(4/3) / R^(2/3)         (entropic confinement)

Reduced form
------------
Lengths in units of ``r0`` (``rho = R / r0``) and energies in units of ``kT``
(so an energy per length is in ``kT / r0``). With ``b = B / (kT r0)`` (the
bending persistence length over r0), ``beta = b^(-1/3)`` and
``t = 1/x = tan(alpha) / pi``::

    w' = w r0 / kT = (1 + t^12) rho^-12 + beta (1 + t^(2/3)) rho^(-2/3)

and, with ``t_alpha = dt/dalpha = sec^2(alpha) / pi``::

    w'_alpha = t_alpha [12 t^11 rho^-12 + (2/3) beta t^(-1/3) rho^(-2/3)]
    w'_rho   = -12 (1 + t^12) rho^-13 - (2/3) beta (1 + t^(2/3)) rho^(-5/3)

The SI partials follow as ``w_alpha = (kT/r0) w'_alpha`` and
``w_R = (kT/r0^2) w'_rho``. ``w_alpha`` diverges like ``alpha^(-1/3)`` at
``alpha -> 0`` (the entropic term); all functions need ``0 < alpha < pi/2`` and
``R > 0``. Everything broadcasts; nothing here imports pint.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "interaction",
    "interaction_partials",
    "interaction_second_partials",
    "reduced_interaction",
    "reduced_interaction_partials",
]


def reduced_interaction(alpha, rho, beta):
    """Reduced interaction ``w' = w r0 / kT`` at reduced radius ``rho = R/r0``.

    ``beta = (B / (kT r0))^(-1/3)``.
    """
    t = np.tan(alpha) / np.pi
    t23 = np.cbrt(t * t)
    return (1.0 + t**12) * rho**-12 + beta * (1.0 + t23) / np.cbrt(rho * rho)


def reduced_interaction_partials(alpha, rho, beta):
    """``(w'_alpha, w'_rho)``: analytic partials of :func:`reduced_interaction`."""
    tan = np.tan(alpha)
    t = tan / np.pi
    t_a = (1.0 + tan * tan) / np.pi
    rho_m23 = 1.0 / np.cbrt(rho * rho)
    rho_m12 = rho**-12
    t23 = np.cbrt(t * t)
    w_a = t_a * (12.0 * t**11 * rho_m12 + (2.0 / 3.0) * beta / np.cbrt(t) * rho_m23)
    w_r = (-12.0 * (1.0 + t**12) * rho_m12 - (2.0 / 3.0) * beta * (1.0 + t23) * rho_m23) / rho
    return w_a, w_r


def _reduced_second_partials(alpha, rho, beta):
    tan = np.tan(alpha)
    t = tan / np.pi
    t_a = (1.0 + tan * tan) / np.pi
    t_aa = 2.0 * tan * (1.0 + tan * tan) / np.pi
    rho_m23 = 1.0 / np.cbrt(rho * rho)
    rho_m12 = rho**-12
    t13 = np.cbrt(t)
    # w'_alpha = t_a * g(t, rho),  g = 12 t^11 rho^-12 + (2/3) beta t^(-1/3) rho^(-2/3)
    g = 12.0 * t**11 * rho_m12 + (2.0 / 3.0) * beta / t13 * rho_m23
    g_t = 132.0 * t**10 * rho_m12 - (2.0 / 9.0) * beta / (t13 * t) * rho_m23
    g_r = (-144.0 * t**11 * rho_m12 - (4.0 / 9.0) * beta / t13 * rho_m23) / rho
    w_aa = t_aa * g + t_a * t_a * g_t
    w_ar = t_a * g_r
    w_rr = (156.0 * (1.0 + t**12) * rho_m12
            + (10.0 / 9.0) * beta * (1.0 + t13 * t13) * rho_m23) / (rho * rho)
    return w_aa, w_ar, w_rr


def _scales(B, kT, r0):
    beta = (B / (kT * r0)) ** (-1.0 / 3.0)
    return beta, kT / r0


def interaction(alpha, radius, B, kT, r0):
    """Marko-Siggia interaction ``w(alpha, R)`` per unit strand length (J/m = N).

    Parameters
    ----------
    alpha : float or array
        Tilt angle (rad), ``0 < alpha < pi/2``.
    radius : float or array
        Superhelix radius R (m).
    B : float
        Bending rigidity (N m^2).
    kT : float
        Thermal energy (J).
    r0 : float
        Hard-core radius (m).
    """
    beta, e = _scales(B, kT, r0)
    return e * reduced_interaction(alpha, np.asarray(radius, float) / r0, beta)


def interaction_partials(alpha, radius, B, kT, r0):
    """Analytic ``(dw/dalpha, dw/dR)`` in (N, N/m)."""
    beta, e = _scales(B, kT, r0)
    w_a, w_r = reduced_interaction_partials(alpha, np.asarray(radius, float) / r0, beta)
    return e * w_a, e / r0 * w_r


def interaction_second_partials(alpha, radius, B, kT, r0):
    """Analytic ``(w_alpha_alpha, w_alpha_R, w_R_R)`` in (N, N/m, N/m^2)."""
    beta, e = _scales(B, kT, r0)
    w_aa, w_ar, w_rr = _reduced_second_partials(alpha, np.asarray(radius, float) / r0, beta)
    return e * w_aa, e / r0 * w_ar, e / r0**2 * w_rr
