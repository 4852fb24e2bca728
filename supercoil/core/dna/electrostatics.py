"""Electrostatics of DNA in monovalent salt: permittivity, Bjerrum and Debye lengths,
effective line charge. Float-only SI kernel (docs/theory/screened-interaction.md#1).

Equations
---------
* Water permittivity (Malmberg & Maryott, J. Res. Natl. Bur. Stand. 56, 1 (1956),
  their fit to the measurements, 0-100 degC, t in degC)::

      eps_r(t) = 87.740 - 0.40008 t + 9.398e-4 t^2 - 1.410e-6 t^3

  (78.30 at 25 degC). Outside 0-100 degC :class:`ValidityError` is raised.
* Bjerrum length ``l_B = e^2 / (4 pi eps0 eps_r kT)`` (0.7158 nm at 25 degC).
* Debye length of a 1:1 salt of concentration c (mol/m^3, i.e. mM)::

      lambda_D = sqrt(eps0 eps_r kT / (2 N_A e^2 c)) = 1 / sqrt(8 pi l_B N_A c)

  (0.3040 nm / sqrt(c / 1 M) at 25 degC).
* Effective line charge (Stigter's far-field matching, Stigter, J. Colloid Interface
  Sci. 53, 296 (1975); Biopolymers 16, 1435 (1977)): a cylinder of radius a with the
  bare charge ``nu0`` (charges per length; B-DNA 2 e per 0.34 nm) in the nonlinear
  Poisson-Boltzmann equation for the reduced potential ``y = e psi / kT`` (y > 0 for
  the sign-flipped, positive charge; the result is even in the sign)::

      y'' + y'/r = kappa^2 sinh y,   y'(a) = -2 l_B nu0 / a,   y -> 0 (r -> inf),

  whose far field is that of a line charge nu in linear (Debye-Hueckel) theory,
  ``y -> 2 l_B nu K0(kappa r)``. ``nu`` is found by shooting inwards from the far
  field (where the linear solution is exact to O(y^3)) and matching the surface
  field; inward integration follows the growing solution K0, so it is stable. In the
  linear limit (small nu0) ``nu = nu0 / (kappa a K1(kappa a))`` (tested).

Everything is in SI: lengths in m, concentrations in mol/m^3, line charges in
elementary charges per metre.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.special import k0e, k1e

from supercoil.exceptions import ValidityError

__all__ = [
    "AVOGADRO",
    "BARE_LINE_CHARGE",
    "ELEMENTARY_CHARGE",
    "VACUUM_PERMITTIVITY",
    "bjerrum_length",
    "debye_length",
    "effective_line_charge",
    "linear_line_charge",
    "water_permittivity",
]

#: elementary charge (C), exact (SI 2019)
ELEMENTARY_CHARGE = 1.602176634e-19
#: Avogadro constant (1/mol), exact (SI 2019)
AVOGADRO = 6.02214076e23
#: vacuum permittivity (F/m), CODATA 2018
VACUUM_PERMITTIVITY = 8.8541878128e-12
_BOLTZMANN = 1.380649e-23
#: bare line charge of B-DNA: two phosphates per 0.34 nm rise (charges per m)
BARE_LINE_CHARGE = 2.0 / 0.34e-9
_KELVIN_0C = 273.15
# reduced potential at which the far-field start is placed (sinh y = y to 1e-12)
_Y_FAR = 2e-6
# steps of the matching in log nu below which the shooting's rounding (rtol 1e-11)
# stops Newton's steps from shrinking
_NOISE = 1e-10


def water_permittivity(temperature):
    """Relative permittivity of water ``eps_r(t)`` (Malmberg & Maryott 1956).

    Parameters
    ----------
    temperature : float or array
        Temperature (K), 273.15 to 373.15 K (the range of the fit).

    Raises
    ------
    ValidityError
        Naming the temperature, outside 0-100 degC.

    Notes
    -----
    Implements docs/theory/screened-interaction.md (SI1).
    """
    t = np.asarray(temperature, dtype=float) - _KELVIN_0C
    if not np.all((t >= 0.0) & (t <= 100.0)):
        bad = np.atleast_1d(t)[~((np.atleast_1d(t) >= 0) & (np.atleast_1d(t) <= 100))][0]
        raise ValidityError(
            f"temperature {bad + _KELVIN_0C:.6g} K is outside 273.15-373.15 K, the range "
            "of the Malmberg-Maryott permittivity fit of water"
        )
    return 87.740 - 0.40008 * t + 9.398e-4 * t * t - 1.410e-6 * t * t * t


def bjerrum_length(temperature):
    """Bjerrum length ``l_B = e^2 / (4 pi eps0 eps_r(T) k_B T)`` (m).

    Implements docs/theory/screened-interaction.md (SI2).
    """
    T = np.asarray(temperature, dtype=float)
    eps = water_permittivity(T)
    return ELEMENTARY_CHARGE**2 / (4.0 * np.pi * VACUUM_PERMITTIVITY * eps * _BOLTZMANN * T)


def debye_length(salt, temperature):
    """Debye length ``lambda_D = (8 pi l_B N_A c)^(-1/2)`` of a 1:1 salt (m).

    Parameters
    ----------
    salt : float or array
        Monovalent salt concentration (ionic strength) c in mol/m^3 (= mM), > 0.
    temperature : float or array
        Temperature (K).

    Raises
    ------
    ValueError
        If the salt concentration is not positive and finite.

    Notes
    -----
    Implements docs/theory/screened-interaction.md (SI2).
    """
    c = np.asarray(salt, dtype=float)
    if not np.all(np.isfinite(c) & (c > 0)):
        raise ValueError(f"salt must be a positive, finite concentration, got {salt!r}")
    return 1.0 / np.sqrt(8.0 * np.pi * bjerrum_length(temperature) * AVOGADRO * c)


def linear_line_charge(nu0, radius, debye):
    """Linear (Debye-Hueckel) limit of the far-field charge: ``nu0 / (kappa a K1(kappa a))``."""
    x = radius / debye
    return nu0 / (x * k1e(x) * math.exp(-x))


def _surface_field(nu, a, kappa, lB, r_far):
    """Reduced surface field ``-y'(a) a / (2 l_B)`` (charges/m) of the far-field
    solution ``y = 2 l_B nu K0(kappa r)`` at ``r_far``, integrated inwards to ``a``, and
    its derivative in ``log nu`` (the sensitivity ``s = dy/dlog nu`` integrated beside
    ``y``: ``s'' + s'/r = kappa^2 cosh(y) s``, starting as ``y`` since the far field is
    linear in ``nu``). Returns ``(inf, nan)`` if the potential blows up before reaching
    a (too much far charge)."""
    from scipy.integrate import solve_ivp  # on first use: only the screened model needs it

    x = kappa * r_far
    k0 = k0e(x) * math.exp(-x)
    k1 = k1e(x) * math.exp(-x)
    y0 = 2.0 * lB * nu * k0
    dy0 = -2.0 * lB * nu * kappa * k1
    k2 = kappa * kappa

    def rhs(r, u):
        return [u[1], k2 * math.sinh(u[0]) - u[1] / r,
                u[3], k2 * math.cosh(u[0]) * u[2] - u[3] / r]

    def blow(r, u):
        return u[0] - 60.0

    blow.terminal = True
    sol = solve_ivp(rhs, (r_far, a), [y0, dy0, y0, dy0], method="DOP853", rtol=1e-11,
                    atol=1e-14, events=blow)
    if sol.status == 1:  # the event fired: the field diverges before r = a
        return math.inf, math.nan
    scale = -a / (2.0 * lB)
    return sol.y[1, -1] * scale, sol.y[3, -1] * scale


def _matching_root(g, hi, at_hi, tol=1e-13):
    """The root in ``log nu`` of the matching ``g(x) -> (value, slope)``, increasing,
    with ``at_hi = g(hi)`` (its value ``>= 0``; ``inf`` allowed: no slope there).

    Newton's steps on the slope of the sensitivity, kept inside the bracket known so
    far: where a step leaves it (or there is no slope) the bracket is bisected, or, with
    no point below the root yet, the point 1 below the lowest one above it is tried (as
    far as ``hi - 60``). Stops when a step is below ``tol * (1 + |x|)`` (brentq's
    ``xtol = rtol = 1e-13`` before), or when the steps stop shrinking below
    ``_NOISE * (1 + |x|)`` (the shooting's rounding).

    Measured against the former brentq on the value alone (same bracket, same
    tolerance) over 1 mM-3 M salt at 25 degC, 0.1-2 times the bare charge and radii
    0.5-2 nm: 3 to 13 shootings instead of 8 to 22 (each with the two sensitivity
    equations), 0.4 to 1.0 times its CPU, the roots equal to 2.3e-12 relative (the
    shooting's rtol is 1e-11).
    """
    lo_x, hi_x = -math.inf, hi
    x, (value, slope), last = hi, at_hi, math.inf
    for _ in range(200):
        if value < 0.0:
            lo_x = x
        else:
            hi_x = x
        step = -value / slope if math.isfinite(value) and slope > 0.0 else math.nan
        new = x + step
        if abs(step) < tol * (1.0 + abs(x)):
            return new
        if lo_x < new < hi_x and abs(step) > 0.5 * last and last < _NOISE * (1.0 + abs(x)):
            return new  # the steps stopped shrinking at the integration's rounding
        if not lo_x < new < hi_x:  # no slope, or the step leaves the bracket: bisect
            new = hi_x - 1.0 if lo_x == -math.inf else 0.5 * (lo_x + hi_x)
            if new < hi - 60.0:  # pragma: no cover - guarded by the bracket argument
                raise ValidityError("effective line charge: no bracket in the PB shooting")
            step = new - x
            if hi_x - lo_x < tol * (1.0 + abs(x)):
                return new
        x, (value, slope), last = new, g(new), abs(step)
    raise ValidityError("effective line charge: the PB shooting did not converge "
                        "in 200 steps")  # pragma: no cover


@lru_cache(maxsize=256)
def _effective_cached(salt, temperature, radius, nu0):
    lB = float(bjerrum_length(temperature))
    lam = float(debye_length(salt, temperature))
    kappa = 1.0 / lam
    nu_lin = linear_line_charge(nu0, radius, lam)
    # start the inward integration where the linear far field of the largest
    # candidate charge has y <= _Y_FAR
    x = max(kappa * radius + 1.0, 2.0)
    while 2.0 * lB * nu_lin * k0e(x) * math.exp(-x) > _Y_FAR:
        x *= 1.25
    r_far = x / kappa

    def g(log_nu):
        field, slope = _surface_field(math.exp(log_nu), radius, kappa, lB, r_far)
        return field - nu0, slope

    hi = math.log(nu_lin) + 1e-9  # the nonlinear far charge is below the linear one
    at_hi = g(hi)
    if at_hi[0] < 0.0:
        return nu_lin  # linear regime to rounding
    return math.exp(_matching_root(g, hi, at_hi))


def effective_line_charge(salt, temperature, radius, nu0=BARE_LINE_CHARGE):
    """Stigter's effective line charge ``nu`` of a charged cylinder (charges per m).

    The line charge whose linear (Debye-Hueckel) field equals the far field of the
    nonlinear Poisson-Boltzmann solution around a cylinder of radius ``radius``
    carrying ``nu0`` charges per length (module docstring; the inward shooting is
    solved to ~1e-10 relative). Results are cached per argument set.

    Parameters
    ----------
    salt : float
        Monovalent salt concentration (mol/m^3), > 0.
    temperature : float
        Temperature (K), 273.15-373.15 K.
    radius : float
        Cylinder radius a (m), > 0 (DNA: about 1 nm).
    nu0 : float
        Bare line charge (charges per m), > 0; default B-DNA, 2/0.34 nm.
        A reduced effective charge (``charge_fraction`` of Maffeo et al., PRL 105,
        158101 (2010)) enters here as ``charge_fraction * nu0``.

    Returns
    -------
    float
        ``nu`` in charges per m.

    Notes
    -----
    Implements docs/theory/screened-interaction.md (SI3).
    """
    for name, v in (("salt", salt), ("radius", radius), ("nu0", nu0)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be positive and finite, got {v!r}")
    water_permittivity(temperature)  # range check
    return _effective_cached(float(salt), float(temperature), float(radius), float(nu0))
