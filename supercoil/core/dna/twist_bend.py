"""Stretched B-DNA with twist-bend coupling: exact worm-like chain and resummed twist term.

docs/theory/melting.md#stretched-phase. Float-only kernel (SI units, broadcasting).

* Worm-like chain at any force: the interpolation of Bouchiat et al. (Biophys. J. 76,
  409, 1999), ``F A / kT = 1/(4 (1-x)^2) - 1/4 + x + sum_{i=2..7} a_i x^i``, inverted
  for the extension per contour length x(F) by the package's one inversion
  (:func:`supercoil.core.dna.phases.wlc_extension`); the free-energy gain per length is the
  Legendre transform ``g(F) = F x - W(x)`` of the polynomial's integral W, so
  ``dg/dF = x`` holds exactly [melting.md#wlc].
* Twist-bend coupling G (Marko & Siggia, Macromolecules 27, 981, 1994): integrating the
  twist out of ``(A_b Om_1^2 + A_b Om_2^2 + C Om_3^2 + 2 G Om_2 Om_3)/2`` leaves the
  stiffness ``A_b - G^2/C`` for bending about the second axis; averaged over the helical
  rotation the long-wavelength bending persistence is the harmonic mean
  ``2/A = 1/A_b + 1/(A_b - G^2/C)`` and the uniform twist stiffness is
  ``C~ = C - G^2/A_b`` [melting.md#twist-bend]. ``A`` is the measured (long-wavelength)
  persistence length; ``A_b`` follows from it.
* Twist term ``-M^2 / (2 kT c(F))`` with the Moroz-Nelson resummation
  ``1/c = 1/C~ + w (1/(4A)) sqrt(kT/(A F))`` (w = 1: Moroz-Nelson; w is a declared
  phenomenological factor of the writhe term, default 1). With G = 0 and w = 1 this is
  :func:`supercoil.core.dna.moroz_nelson.effective_twist_rigidity` divided by kT.
"""

from __future__ import annotations

import numpy as np

from supercoil.exceptions import ValidityError

from . import phases as _ph
from .phases import PhaseGibbs

__all__ = [
    "BOUCHIAT_COEFFICIENTS",
    "check_force",
    "check_positive",
    "effective_twist_stiffness",
    "stretched_gibbs",
    "twist_bend_renormalisation",
    "wlc_extension",
    "wlc_gibbs_gain",
]

#: a_2 ... a_7 of the worm-like-chain interpolation (Bouchiat et al., Biophys. J. 76, 409,
#: 1999); the one copy is in :mod:`supercoil.core.dna.phases`
BOUCHIAT_COEFFICIENTS = _ph.BOUCHIAT_COEFFICIENTS


def check_force(force, what, allow_zero=False):
    """Force array (N); :class:`ValidityError` naming ``what`` and the force if not valid."""
    f = np.asarray(force, dtype=float)
    bad = ~np.isfinite(f) | ((f < 0.0) if allow_zero else (f <= 0.0))
    if np.any(bad):
        i = np.flatnonzero(np.broadcast_to(bad, f.shape))[0]
        need = "non-negative" if allow_zero else "positive"
        raise ValidityError(f"{what} undefined at force {np.ravel(f)[i] * 1e12:.6g} pN: "
                            f"the force must be finite and {need}")
    return f


def check_positive(value, name, what):
    """``value`` as an array; :class:`ValidityError` naming ``name`` unless finite, > 0."""
    v = np.asarray(value, dtype=float)
    if np.any(~np.isfinite(v) | (v <= 0.0)):
        raise ValidityError(f"{what}: {name} must be finite and positive, got {v}")
    return v


def wlc_extension(force, A, kT):
    """Extension per contour length x(F) of the worm-like chain (Bouchiat interpolation).

    Parameters
    ----------
    force : float or array
        Force F (N), positive.
    A : float
        Bending persistence length (m).
    kT : float
        Thermal energy (J).

    Returns
    -------
    x, dx_dF : arrays
        Relative extension (0 <= x < 1) and its derivative (1/N).
    """
    f = check_force(force, "worm-like chain extension")
    return _ph.wlc_extension(f, A, kT)


def wlc_gibbs_gain(force, A, kT):
    """``g(F) = F x - W(x)`` (N), ``dg/dF = x``, ``d2g/dF2 = dx/dF`` of the worm-like chain.

    Implements docs/theory/melting.md (MT2).

    ``-g`` is the Gibbs free energy per contour length of a torsionless stretched chain
    relative to the relaxed one [melting.md#wlc].
    """
    f = check_force(force, "worm-like chain free energy")
    return _ph.wlc_exact_free_energy_gain(f, A, kT, slope=True)


def twist_bend_renormalisation(A, C, G):
    """Intrinsic bending ``A_b`` and uniform twist stiffness ``C~`` (m) for coupling G (m).

    Implements docs/theory/melting.md (MT3, MT4).

    ``A_b = ((A + u) + sqrt(A^2 + u^2)) / 2`` with ``u = G^2/C`` solves
    ``2/A = 1/A_b + 1/(A_b - u)``; ``C~ = C - G^2/A_b`` (> 0 for every G)
    [melting.md#twist-bend]. G = 0 gives ``(A, C)`` exactly.
    """
    A = check_positive(A, "A", "twist-bend renormalisation")
    C = check_positive(C, "C", "twist-bend renormalisation")
    G = np.asarray(G, dtype=float)
    if np.any(~np.isfinite(G)):
        raise ValidityError(f"twist-bend renormalisation: G must be finite, got {G}")
    u = G * G / C
    Ab = 0.5 * ((A + u) + np.sqrt(A * A + u * u))
    return Ab, C - G * G / Ab


def effective_twist_stiffness(force, A, C, G, kT, writhe_factor=1.0):
    """Twist persistence ``c(F)`` (m) of stretched DNA and ``dc/dF`` (m/N).

    Implements docs/theory/melting.md (MT5).

    ``1/c = 1/C~ + w sqrt(kT/(A F)) / (4 A)`` [melting.md#twist-bend]; with G = 0 and
    w = 1 the Moroz-Nelson resummation. Raises :class:`ValidityError` naming the force
    where F <= 0.
    """
    f = check_force(force, "effective twist stiffness")
    _, Ct = twist_bend_renormalisation(A, C, G)
    k = writhe_factor * np.sqrt(kT / A) / (4.0 * A)
    inv = 1.0 / Ct + k / np.sqrt(f)
    c = 1.0 / inv
    # d(1/c)/dF = -k / (2 F^1.5)  =>  dc/dF = c^2 k / (2 F^1.5)
    return c, c * c * k / (2.0 * f * np.sqrt(f))


def stretched_gibbs(F, M, A, C, G, kT, writhe_factor=1.0):
    """Stretched B-DNA: ``phi_s = -g(F) - M^2 / (2 kT c(F))`` and its derivatives.

    Implements docs/theory/melting.md (MT1).

    Parameters
    ----------
    F : float or array
        Force (N), positive.
    M : float or array
        Torque (N m), broadcast with F.
    A : float
        Long-wavelength bending persistence length (m).
    C : float
        Bare twist persistence length (m).
    G : float
        Twist-bend coupling (m); 0 gives the plain Moroz-Nelson resummation.
    kT : float
        Thermal energy (J).
    writhe_factor : float
        Factor w of the Moroz-Nelson writhe term (1: the theory).

    Returns
    -------
    PhaseGibbs
        ``phi`` (N), ``dphi_dF = -x`` (1), ``dphi_dM = -Omega`` (1/m), ``d2phi_dM2`` (1/(N m^2)).
    """
    F, M = np.broadcast_arrays(np.asarray(F, dtype=float), np.asarray(M, dtype=float))
    g, x, _ = wlc_gibbs_gain(F, A, kT)
    c, dc = effective_twist_stiffness(F, A, C, G, kT, writhe_factor)
    q = M * M / (2.0 * kT)
    phi = -g - q / c
    dphi_dF = -x + q * dc / (c * c)
    dphi_dM = -M / (kT * c)
    return PhaseGibbs(phi, dphi_dF, dphi_dM, -1.0 / (kT * c))
