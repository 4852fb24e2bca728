"""Stability maps of the DNA model family, generated from the model and interaction registries.

One map per registered model and (for models with a plectoneme helix) per registered
interaction, so a model added to the registry enters the maps without new code here. Each
cell is one hat curve at a force over symmetric turns up to a supercoiling density of
+-0.15 (past full coiling at every force of the grid), for one molecule (the given set, with
150 mM salt if it has none): the y axis is the salt for interactions that need one, else the
bending persistence A (elasticity).

References (a second method, not the model's own formulas):

* the contract of :mod:`supercoil.dna.models.base`: finite numbers, extension even and
  torque odd in N (the grid is symmetric), phase codes of the shared set; ``0 <= z <= L``
  on points not flagged ``short_tail``, or else the warning of the shared limit
  (:func:`supercoil.dna.validity.extension_messages`, which names such a point): an
  extension outside its physical range with that warning is flagged, without it WRONG
  (another warning of the same call does not excuse it);
* models derived from one free energy (``has_free_energy``): at interior points (same
  phase as both neighbours) ``z = -dG/dF`` and ``M = (1/2 pi) dG/dN`` by central
  differences of the model's free energy, to ``1e-5 L`` and ``1e-5 max|M|``.

A cell whose hat curve takes longer than :data:`HANG_SECONDS` is WRONG ("hang").
"""

from __future__ import annotations

import time
import warnings

import numpy as np

from supercoil import display
from supercoil.benchmark.stability.classify import (
    Axis,
    call,
    finite_problems,
    log_grid,
    verdict,
)

#: a cell slower than this (s) is classified WRONG: a solver that does not come back
HANG_SECONDS = 20.0
#: the words of the shared limit's warning on an extension outside [0, L]
#: (:func:`supercoil.dna.validity.extension_messages`)
EXTENSION_WARNING = "lies outside [0, L"
#: supercoiling density at the ends of each cell's turns grid
SIGMA_MAX = 0.15
_HELICAL_REPEAT = 3.57e-9  # m per helical turn (the package's h)


def cases():
    """``(key, model name, interaction name or None)`` of every registered combination."""
    from supercoil.benchmark.family import cases as family_cases

    return [(f"family {key}", name, inter) for key, name, inter in family_cases()]


def _needs_salt(inter, dna):
    """Whether the interaction reads the DNA's salt (it rejects a DNA without one)."""
    from supercoil.dna.interactions import get_interaction
    from supercoil.exceptions import ParameterError

    if inter is None:
        return False
    try:
        get_interaction(inter).check(dna.replace(salt=None).si)
    except ParameterError:
        return True
    return False


def _interior(phase, neighbours):
    return np.all([p == phase for p in neighbours], axis=0)


def free_energy_problems(dna, F, model, inter, thermal):
    """z = -dG/dF and M = dG/dN / 2 pi at interior points, by central differences.

    One hat curve over the forces ``F, F -+ h_F`` and the turns ``N, N -+ h_N``
    (force-major tables), its ``free_energy`` column the G (one free-energy call where the
    table has none): the points, their neighbours' phases and the differences all come
    from that call.
    """
    import supercoil as sc

    u = sc.ureg
    L = dna.si.length
    n = np.linspace(0.05, 0.95, 5) * SIGMA_MAX * L / _HELICAL_REPEAT
    hN, hF = 1e-4, 1e-5 * F
    turns = np.concatenate([n - hN, n, n + hN])
    forces = np.array([F - hF, F, F + hF])
    kw = {"model": model, "thermal": thermal, **({"interaction": inter} if inter else {})}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        df = sc.hat_curve(dna, forces * u.pN, turns, **kw)
        if "free_energy" in df:  # the table carries G: a second solve of the same points
            g = (df["free_energy"].to_numpy() * u(df.attrs["units"]["free_energy"])).m_as("J")
        else:
            g = sc.free_energy(dna, forces * u.pN, turns, **kw).m_as("J")
        g = np.asarray(g).reshape(3, 3, n.size)
    z = display.from_display(df["extension"].to_numpy().reshape(3, 3, n.size)[1, 1],
                             "extension")
    M = display.from_display(df["torque"].to_numpy().reshape(3, 3, n.size)[1, 1], "torque")
    ph = df["phase"].to_numpy().reshape(3, 3, n.size)
    inner = _interior(ph[1, 1], [ph[1, 0], ph[1, 2], ph[0, 1], ph[2, 1]]) & (z > 1e-3 * L)
    if not inner.any():
        return []
    dGdN = (g[1, 2] - g[1, 0]) / (2 * hN)
    dGdF = (g[2, 1] - g[0, 1]) / (2 * display.from_display(hF, "force"))
    dz = np.abs(-dGdF - z)[inner].max()
    dM = np.abs(dGdN / (2 * np.pi) - M)[inner].max()
    out = []
    if dz > 1e-5 * L:
        out.append(f"z differs from -dG/dF by {dz:.3e} m (> 1e-5 L)")
    if dM > 1e-5 * max(np.abs(M).max(), 1e-30):
        out.append(f"torque differs from dG/dN / 2 pi by {dM:.3e} N m")
    return out


def contract_problems(df, dna, symmetric=True):
    """``(problems, soft)`` of the contract on one hat curve over symmetric turns: for a
    model symmetric in N its symmetries (problems), and an extension outside [0, L] on a
    point not flagged ``short_tail`` (soft: WRONG unless the call warned of it,
    :data:`EXTENSION_WARNING`)."""
    L = dna.si.length
    z = display.from_display(df["extension"].to_numpy(), "extension")
    M = df["torque"].to_numpy()
    short = df["short_tail"].to_numpy(bool)
    out, soft = [], []
    bad = ~short & ((z < -1e-9 * L) | (z > L * (1 + 1e-9)))
    if bad.any():
        soft.append(f"unflagged extension {z[bad][0]:.6g} m outside [0, L]")
    if not symmetric:
        return out, soft
    if not np.allclose(z, z[::-1], rtol=1e-9, atol=1e-12 * L):
        out.append("extension is not even in N")
    if not np.allclose(M, -M[::-1], rtol=1e-9, atol=1e-12 * max(np.abs(M).max(), 1e-300)):
        out.append("torque is not odd in N")
    return out, soft


def _cell(d, F, turns, kw, model, thermal):
    """``(outcome, detail)`` of one cell: the hat curve of ``d`` at ``F`` over ``turns``."""
    import supercoil as sc

    t0 = time.perf_counter()
    df, exc, warns = call(lambda: sc.hat_curve(d, F * sc.ureg.pN, turns, **kw))
    seconds = time.perf_counter() - t0
    problems, soft = [], []
    if seconds > HANG_SECONDS:
        problems.append(f"hang: the hat curve took {seconds:.1f} s (> {HANG_SECONDS} s)")
    elif df is not None:
        num = df.select_dtypes("number")
        problems = finite_problems({c: num[c].to_numpy() for c in num.columns})
        if not problems:
            problems, soft = contract_problems(df, d, model.symmetric_in_turns)
        if not problems and model.has_free_energy(thermal) and F > 0:
            problems = free_energy_problems(d, F, kw["model"], kw.get("interaction"), thermal)
    if soft and not any(EXTENSION_WARNING in str(w.message) for w in warns):
        problems, soft = problems + soft, []  # no warning names the extension
    return verdict(exc, warns, problems, soft=soft)


def family_map(dna, name, inter, quick, thermal=True):
    """The map of one model (and interaction) over force x (salt or A)."""
    import supercoil as sc
    from supercoil.dna.models import get_model

    u = sc.ureg
    if dna.salt is None:  # the seed set has none: the family's molecules carry 150 mM
        dna = dna.replace(salt=150 * u.mM)
    forces = np.concatenate([[0.0], log_grid(1e-2, 1e3, 5 if quick else 16)])
    salt = _needs_salt(inter, dna)
    if salt:
        ys = log_grid(1.0, 3000.0, 2 if quick else 8)  # mM
        axis = Axis("salt", "monovalent salt [mM]", "mM", ys)
    else:
        ys = log_grid(10.0, 200.0, 2 if quick else 8)  # nm
        axis = Axis("bending_persistence", "bending persistence A [nm]", "nm", ys)
    model = get_model(name)
    kw = {"model": name, "thermal": thermal, **({"interaction": inter} if inter else {})}
    out = np.empty((ys.size, forces.size), dtype=object)
    for j, y in enumerate(ys):
        d = dna.replace(salt=y * u.mM) if salt else dna.replace(bending_persistence=y * u.nm)
        nmax = SIGMA_MAX * d.si.length / _HELICAL_REPEAT
        turns = np.linspace(-nmax, nmax, 21 if quick else 81)
        for i, F in enumerate(forces):
            out[j, i] = _cell(d, F, turns, kw, model, thermal)
    key = f"hat_curve {name}" + (f"/{inter}" if inter else "")
    return key, Axis("force", "force [pN]", "pN", forces), axis, out
