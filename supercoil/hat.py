"""Hat curves of DNA in a magnetic tweezers: extension versus turns at fixed forces.

MODEL.md section 6 (paper Example III and its DNA figure). Unit wrappers over
:mod:`supercoil.core.hat_curve`, where the phases, the buckling point, the
linking balance of the plectoneme phase, the post-buckling slope and the
short-tail flag are derived. The plectoneme equilibrium is solved once per
force.
"""

from __future__ import annotations

import warnings
from functools import lru_cache

import numpy as np
import pandas as pd

from .core import hat_curve as _hc
from .core import moroz_nelson as _mn
from .exceptions import ValidityWarning
from .plectoneme import _check_dna, _force, warn_force_range
from .tables import make_table, provenance
from .units import U, as_turns, magnitude, quantity

__all__ = [
    "HELICAL_REPEAT",
    "PHASES",
    "buckling_turns",
    "hat_curve",
    "plot_hat_curves",
    "post_buckling_slope",
]

#: DNA helical repeat h (m per helical turn, 10.5 bp): Lk_0 = L / h
HELICAL_REPEAT = 3.57e-9
#: phase labels of the ``phase`` column, indexed by the kernel's phase code
PHASES = np.array(["stretched", "plectoneme", "fully coiled"], dtype=object)
_PHASE_CATEGORIES = list(PHASES)  # the phase column is categorical: cheap for long tables

_UNITS = {
    "force": "pN",
    "turns": "turn",
    "extension": "nm",
    "phase": "",
    "torque": "pN nm",
    "plectoneme_length": "nm",
    "supercoiling_density": "",
    "eta": "",
    "short_tail": "",
}


def _args(dna, force, thermal):
    if not isinstance(thermal, bool | np.bool_):
        raise TypeError(f"thermal must be True or False, got {thermal!r}")
    si = _check_dna(dna)
    f = np.atleast_1d(_force(force))
    if f.ndim != 1:
        raise ValueError(f"force must be a scalar or 1-D, got shape {f.shape}")
    return si, f, (si.length, si.bending_rigidity, si.torsional_rigidity, si.kT, si.radius,
                   bool(thermal))


def buckling_turns(dna, force, thermal=True):
    """Turns at buckling ``N_b = C omega L / (2 pi C_eff)`` at each force [MODEL.md s.6].

    Returns
    -------
    Quantity [turn], number of turns (1-D, one per force). The hat
    curve buckles at ``+N_b`` and ``-N_b``.
    """
    _, f, a = _args(dna, force, thermal)
    return quantity(_hc.buckling_turns(f, *a), U.turn)


def post_buckling_slope(dna, force, thermal=True):
    """Post-buckling slope ``dz/dN`` for N > N_b, in nm per turn, at each force.

    ``dz/dN = -2 pi zeta_inf / D`` with ``D = tau - (C/C_eff - 1) omega`` and
    ``zeta_inf = 1 - Q^(-1/2)/2`` (athermal: ``-2 pi / tau``); derivation in
    :mod:`supercoil.core.hat_curve`. The slope for N < -N_b is the opposite.

    Returns
    -------
    Quantity [nm/turn] (negative), 1-D.

    Warns
    -----
    ValidityWarning
        (thermal) where zeta's long-tail factor is <= 0 (the slope would be
        positive: 0.0954-0.1218 pN for the seed set) or < 0.5 (the
        Moroz-Nelson expansion has not converged).
    """
    si, f, a = _args(dna, force, thermal)
    slope = _hc.post_buckling_slope(f, *a)
    if thermal:
        par = _hc.hat_parameters(f, *a[:-1], thermal=True, check_zeta=False)
        Q = _mn.zeta_bracket(f, par.torque, si.bending_rigidity, si.kT)
        _warn_long_tail(f, Q, np.ones(f.shape, bool))
    return quantity(slope * 1e9, U.nm_per_turn)


def hat_curve(dna, force, turns, thermal=True, short_tail_length=None):
    """Hat curves: extension, torque and phase versus turns at fixed forces.

    Built exactly as MODEL.md section 6: stretched phase (torque
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
    NoEquilibriumError
        Naming the force, where no plectoneme equilibrium exists.
    ValidityError
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
    si, f, a = _args(dna, force, thermal)
    n = np.atleast_1d(as_turns(turns, "turns"))
    if n.ndim != 1:
        raise ValueError(f"turns must be a scalar or 1-D, got shape {n.shape}")
    if short_tail_length is None:
        short = None
    else:
        short = magnitude(short_tail_length, U.m, "short_tail_length")
        if not (np.ndim(short) == 0 and short >= 0):
            raise ValueError(f"short_tail_length must be a non-negative scalar, "
                             f"got {short_tail_length}")
    F = np.repeat(f, n.size)
    N = np.tile(n, f.size)
    hp = _hc.hat_curve_points(N, F, *a[:-1], thermal=a[-1], short_tail_length=short)
    L = si.length
    _warn(F, N, hp, thermal, si)
    if short is None:
        short = _hc.SHORT_TAIL_PERSISTENCE_LENGTHS * si.bending_persistence
    return make_table(
        {
            "force": F * 1e12,
            "turns": N,
            "extension": hp.extension * 1e9,
            "phase": pd.Categorical.from_codes(hp.phase, categories=_PHASE_CATEGORIES),
            "torque": hp.torque * 1e21,
            "plectoneme_length": hp.plectoneme_length * 1e9,
            "supercoiling_density": N * (HELICAL_REPEAT / L),
            "eta": N * (2.0 * np.pi * si.wlc_persistence / L),
            "short_tail": hp.short_tail,
        },
        _UNITS,
        provenance(
            _parameters(dna),
            scene="hat curve (MODEL.md section 6)",
            thermal=bool(thermal),
            short_tail_length=f"{short * 1e9:.6g} nm",
            helical_repeat=f"{HELICAL_REPEAT * 1e9:.6g} nm",
        ),
    )


@lru_cache(maxsize=32)
def _parameters(dna):
    """``dna.as_dict()`` once per molecule (formatting pint units costs ~50 us)."""
    return dna.as_dict()


def _warn(F, N, hp, thermal, si):
    warn_force_range(F)
    den = (N < 0) & (F > _hc.DENATURATION_FORCE)
    if np.any(den):
        warnings.warn(
            f"negative turns at {F[den].max() * 1e12:.6g} pN (> 0.8 pN): real DNA denatures "
            "under negative supercoiling there; the model ignores denaturation",
            ValidityWarning,
            stacklevel=3,
        )
    if thermal:
        zeta_bad = ~hp.short_tail & ~((hp.zeta > 0) & (hp.zeta <= 1))
        if np.any(zeta_bad):
            i = np.flatnonzero(zeta_bad)[0]
            warnings.warn(
                f"Moroz-Nelson zeta = {hp.zeta[i]:.4g} lies outside (0, 1] at force "
                f"{F[i] * 1e12:.6g} pN, turns {N[i]:.6g}: the extension is not valid there",
                ValidityWarning,
                stacklevel=3,
            )
            return
        Q = _mn.zeta_bracket(F, hp.torque, si.bending_rigidity, si.kT)
        _warn_long_tail(F, Q, hp.phase != _hc.FULLY_COILED, N)


#: Below this Moroz-Nelson bracket Q the long-tail factor 1 - Q^(-1/2)/2 < 0.5: the
#: expansion in 1/sqrt(Q) has not converged and the thermal extension is qualitative.
CONVERGED_BRACKET = 1.0


def _warn_long_tail(F, Q, where, N=None):
    """ValidityWarning where zeta's long-tail factor ``1 - Q^(-1/2)/2`` is <= 0 or < 0.5."""
    def at(i):
        return f"force {F[i] * 1e12:.6g} pN" + (f", turns {N[i]:.6g}" if N is not None else "")

    bad = where & (Q <= 0.25)
    if np.any(bad):
        i = np.flatnonzero(bad)[0]
        warnings.warn(
            f"Moroz-Nelson zeta is not valid at {at(i)}: its long-tail factor "
            f"1 - Q^(-1/2)/2 = {1 - 0.5 / np.sqrt(Q[i]):.4g} <= 0 (the extension would grow "
            "with turns)", ValidityWarning, stacklevel=4)
        return
    rough = where & (Q < CONVERGED_BRACKET)
    if np.any(rough):
        i = np.flatnonzero(rough)[0]
        warnings.warn(
            f"Moroz-Nelson expansion not converged at {at(i)}: the long-tail factor "
            f"1 - Q^(-1/2)/2 = {1 - 0.5 / np.sqrt(Q[i]):.3g} < 0.5 (bracket Q < 1), so the "
            "thermal extension and post-buckling slope are qualitative there "
            "(below 0.201 pN in the plectoneme phase for the seed set)", ValidityWarning,
            stacklevel=4)


def plot_hat_curves(df, path=None, dna=None):
    """Plot a :func:`hat_curve` table: extension vs N, vs eta, and torque vs N.

    Short-tail points are drawn dotted. Returns the figure; writes ``path`` if given.
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5), constrained_layout=True)
    for force, g in df.groupby("force", sort=True):
        g = g.sort_values("turns")
        label = f"{force:g} pN"
        long_tail = ~g["short_tail"].to_numpy()
        line = None
        for ax, x, y in ((axes[0], "turns", "extension"), (axes[1], "eta", "extension"),
                         (axes[2], "turns", "torque")):
            xs, ys = g[x].to_numpy(), g[y].to_numpy()
            ym = np.where(long_tail, ys, np.nan)
            (ln,) = ax.plot(xs, ym, label=label, color=None if line is None else line)
            line = ln.get_color()
            ax.plot(xs, np.where(long_tail, np.nan, ys), ":", color=line)
    axes[0].set(xlabel="turns N", ylabel="extension z [nm]")
    axes[1].set(xlabel=r"$\eta = 2\pi N \xi_T / L$", ylabel="extension z [nm]")
    axes[2].set(xlabel="turns N", ylabel="torque [pN nm]")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(title="force")
    thermal = df.attrs.get("provenance", {}).get("thermal")
    fig.suptitle("DNA hat curves (Marko-Siggia plectoneme"
                 + (", Moroz-Nelson tail)" if thermal else ", athermal)")
                 + "; dotted: tail shorter than the short-tail length")
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig
