"""Synthetic rotation curves (examples, validation, tests) from any registered DNA model."""

from __future__ import annotations

import numpy as np

from supercoil import display
from supercoil._checks import check_flag, scalar
from supercoil.dna import validity as _v
from supercoil.dna.fitting.fit import resolve_model
from supercoil.dna.interactions import DEFAULT_INTERACTION
from supercoil.dna.models import DEFAULT_MODEL
from supercoil.exceptions import FitError
from supercoil.tables import make_table, provenance
from supercoil.units import U, as_turns, magnitude, quantity

__all__ = ["simulate_rotation_curves", "valid_turns_range"]


def valid_turns_range(dna, force, min_tail=None, thermal=True, model=DEFAULT_MODEL,
                      interaction=DEFAULT_INTERACTION):
    """Largest |N| (turns) at each force whose tail is still longer than ``min_tail``.

    Beyond it the hat curve enters the short-tail region where the Moroz-Nelson
    extension factor is not valid (docs/theory/li-zhao.md). ``min_tail``
    defaults to 4 bending persistence lengths (one more than the kernel's
    short-tail flag, so that a turns offset of a turn or two keeps the data
    valid). From :meth:`~supercoil.dna.models.base.DNAModel.turns_at_tail_length`: for
    ``"li-zhao"`` exact, ``N_b + (L - l_min) D / (2 pi)`` with the linking rate D; by
    default from the buckling constants, ``N_b + z_b (1 - l_min / L) / |dz/dN|`` (the
    plectoneme phase taken as linear).

    Returns a float array (turns), one per force (empty for no force).

    Raises
    ------
    FitError
        For a model that does not buckle at a force (no finite range).
    ValueError, NoEquilibriumError
        Forces not finite, not 1-D, or not positive (as every DNA function).
    """
    thermal = check_flag(thermal, "thermal")
    si = _v.check_dna(dna)
    m, inter = resolve_model(model, interaction)
    if m.uses_interaction:
        _v.check_interaction(inter, si)
    F = _v.checked_forces(force)  # the shared DNA force check (finite, positive, 1-D)
    if F.size == 0:
        return np.empty(0)
    lmin = 4 * si.bending_persistence if min_tail is None else float(
        magnitude(min_tail, U.m, "min_tail"))
    n = m.turns_at_tail_length(F, lmin, si, thermal, inter)
    if not np.all(np.isfinite(n)):
        i = int(np.flatnonzero(~np.isfinite(n))[0])
        raise FitError(f"model {m.name!r} does not buckle at force {F[i] * 1e12:.6g} pN: no "
                       "finite valid turns range; give the turns explicitly")
    return n


def _labels(molecules):
    """``(labels, has_molecule_column)``; TypeError/ValueError naming ``molecules``."""
    if molecules is None:
        return ["m1"], False
    if isinstance(molecules, bool) or isinstance(molecules, float | str | bytes):
        raise TypeError(f"molecules must be a positive integer or a sequence of labels, got "
                        f"{molecules!r}")
    if isinstance(molecules, int | np.integer):
        if molecules < 1:
            raise ValueError(f"molecules must be at least 1 (the number of molecules), got "
                             f"{molecules}")
        return [f"m{i + 1}" for i in range(int(molecules))], True
    try:
        labels = [str(m) for m in molecules]
    except TypeError:
        raise TypeError("molecules must be a positive integer or a sequence of labels, got "
                        f"{type(molecules).__name__}") from None
    if not labels:
        raise ValueError("molecules is empty: give at least one label (or a count)")
    if len(set(labels)) != len(labels):
        dup = next(x for x in labels if labels.count(x) > 1)
        raise ValueError(f"molecules repeats the label {dup!r}: the molecules' rows would "
                         "merge; give distinct labels")
    return labels, True


def _per_molecule(values, n, name):
    """One finite value, or one per molecule, as an (n,) array; ValueError naming ``name``."""
    a = np.asarray(values, dtype=float)
    if a.shape not in ((), (1,), (n,)):
        raise ValueError(f"{name} has shape {a.shape}; give one value, or one per molecule "
                         f"(shape ({n},) for {n} molecule{'s' if n > 1 else ''})")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got {values!r}")
    return np.broadcast_to(a, (n,))


def _offsets(turns_offset, extension_offset, n):
    n0 = _per_molecule(as_turns(turns_offset, "turns_offset"), n, "turns_offset")
    z0 = _per_molecule(magnitude(extension_offset if extension_offset is not None
                                 else 0 * U.nm, U.m, "extension_offset"), n,
                       "extension_offset")
    return n0, z0


def _rng(seed):
    """A numpy Generator from ``seed``; TypeError/ValueError naming ``seed``."""
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or isinstance(seed, np.random.SeedSequence):
        return np.random.default_rng(seed)
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
        raise TypeError(f"seed must be None, a non-negative integer or a "
                        f"numpy.random.Generator, got {type(seed).__name__} {seed!r}")
    if seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed}")
    return np.random.default_rng(int(seed))


def _forces(force):
    """Checked forces (N, 1-D, finite, positive: the shared DNA check); not empty."""
    F = _v.checked_forces(force)
    if F.size == 0:
        raise ValueError("force is empty: give at least one force (one rotation curve per "
                         "force)")
    return F


def _points_per_force(n):
    if isinstance(n, bool) or not isinstance(n, int | np.integer):
        raise TypeError(f"points_per_force must be an integer >= 2, got {n!r}")
    if n < 2:
        raise ValueError(f"points_per_force must be >= 2 (a curve from -N to +N), got {n}")
    return int(n)


#: units of the simulated extension column and their factor from metres
_EXTENSION_UNITS = ("um", "nm")


def _torque_sd(torque_noise):
    """The torque noise (N m) or None; FitError unless finite and >= 0."""
    if torque_noise is None:
        return None
    sd_t = scalar(magnitude(torque_noise, U.N * U.m, "torque_noise"), "torque_noise")
    if not (np.isfinite(sd_t) and sd_t >= 0):
        raise FitError("torque_noise must be finite and >= 0, got "
                       f"{display.text(sd_t, 'torque', 'g')}")
    return sd_t


def _add_torque(table, units, torques, sd_t, sigma_column):
    """The ``torque`` (and ``torque_sigma``) columns, pN nm."""
    table["torque"] = np.concatenate(torques)
    units["torque"] = "pN nm"
    if sigma_column:
        table["torque_sigma"] = np.full(len(table["force"]),
                                        display.to_display(sd_t, "torque"))
        units["torque_sigma"] = "pN nm"


def simulate_rotation_curves(dna, force, turns=None, *, points_per_force=110, noise=None,
                             turns_offset=0.0, extension_offset=None, molecules=None, seed=None,
                             thermal=True, extension_unit="um", sigma_column=False,
                             model=DEFAULT_MODEL, interaction=DEFAULT_INTERACTION,
                             torque_noise=None):
    """Synthetic rotation curves: a hat-curve model plus offsets and Gaussian noise.

    Parameters
    ----------
    dna : DNA
        The true parameters.
    force : Quantity [force], array
        One rotation curve per force (and per molecule).
    turns : array, optional
        Applied turns of every curve; default ``points_per_force`` points evenly
        over +-:func:`valid_turns_range` at each force.
    noise : Quantity [length], optional
        Standard deviation of the Gaussian extension noise (default 5 nm).
    turns_offset, extension_offset : float / Quantity or sequence, optional
        True offsets: the data are ``hat(N - turns_offset) + extension_offset``
        (one value, or one per molecule). Default 0 turns and 0 nm.
    molecules : int or sequence of str, optional
        Number (labels ``m1``, ``m2``, ...) or labels of molecules; with it the
        table has a ``molecule`` column.
    seed : int, numpy.random.SeedSequence or numpy.random.Generator, optional
        Random seed (a non-negative integer; reproducible data).
    thermal : bool
        Thermal (default) or athermal hat curve.
    extension_unit : str
        Unit of the extension column (``"um"`` or ``"nm"``).
    sigma_column : bool
        Add a ``sigma`` column (nm) holding the noise level (and, with
        ``torque_noise``, a ``torque_sigma`` column in pN nm).
    model, interaction : str or instance
        The DNA model (default ``"li-zhao"``) and interaction (``"hard-core"``).
    torque_noise : Quantity [torque], optional
        With it the table has a ``torque [pN nm]`` column: the model torque
        (sign of the turns) plus Gaussian noise of this standard deviation
        (drawn after the extension noise of each molecule).

    Raises
    ------
    TypeError
        ``molecules``, ``seed`` or ``points_per_force`` of the wrong type.
    ValueError
        ``force`` or ``turns`` empty, not finite, not 1-D (a force <= 0 is a
        NoEquilibriumError); ``molecules`` < 1, empty or with repeated labels;
        ``turns_offset`` / ``extension_offset`` neither one value nor one per
        molecule; a negative ``seed``; ``points_per_force`` < 2.
    FitError
        ``noise``, ``torque_noise`` negative or not finite; an unknown
        ``extension_unit``.

    Returns
    -------
    pandas.DataFrame
        The table convention of :func:`~supercoil.read_tweezers_csv`:
        ``[molecule,] force [pN], turns, extension [extension_unit][, sigma [nm]]``
        ``[, torque [pN nm][, torque_sigma [pN nm]]]``.
    """
    thermal = check_flag(thermal, "thermal")
    sigma_column = check_flag(sigma_column, "sigma_column")
    _v.check_dna(dna)
    if extension_unit not in _EXTENSION_UNITS:
        raise FitError(f"extension_unit must be one of {list(_EXTENSION_UNITS)}, got "
                       f"{extension_unit!r}")
    m, inter = resolve_model(model, interaction)
    if m.uses_interaction:
        _v.check_interaction(inter, dna.si)  # the scales the public DNA functions check
    rng = _rng(seed)
    F = _forces(force)
    sd = 5e-9 if noise is None else scalar(magnitude(noise, U.m, "noise"), "noise")
    if not (np.isfinite(sd) and sd >= 0):
        raise FitError(f"noise must be finite and >= 0, got {display.text(sd, 'extension', 'g')}")
    sd_t = _torque_sd(torque_noise)
    labels, has_mol = _labels(molecules)
    n0, z0 = _offsets(turns_offset, extension_offset, len(labels))
    if turns is None:
        nmax = valid_turns_range(dna, quantity(F, U.N), thermal=thermal, model=m,
                                 interaction=interaction)
        grids = [np.linspace(-x, x, _points_per_force(points_per_force)) for x in nmax]
    else:
        n = _v.checked_turns(turns, dna.si)  # the shared DNA turns check
        if n.size == 0:
            raise ValueError("turns is empty: give at least one number of turns")
        grids = [n] * len(F)
    factor = display.spec(extension_unit)[1]  # m -> the unit asked for (pint)
    N = np.concatenate(grids)
    FF = np.concatenate([np.full(len(g), f) for g, f in zip(grids, F, strict=True)])
    mol, Fs, Ns, Zs, Ts = [], [], [], [], []
    for i, lab in enumerate(labels):
        pts = m.points(N - n0[i], FF, dna.si, thermal, inter, None)
        z = np.asarray(pts.extension, dtype=float)
        z = z + z0[i] + rng.normal(0.0, sd, z.shape)
        if sd_t is not None:
            tq = np.asarray(pts.torque, dtype=float)
            Ts.append(display.to_display(tq + rng.normal(0.0, sd_t, tq.shape), "torque"))
        mol.extend([lab] * len(N))
        Fs.append(display.to_display(FF, "force"))
        Ns.append(N)
        Zs.append(z * factor)
    table = {"molecule": mol} if has_mol else {}
    table.update(force=np.concatenate(Fs), turns=np.concatenate(Ns),
                 extension=np.concatenate(Zs))
    units = {"molecule": "", "force": "pN", "turns": "", "extension": extension_unit}
    if sigma_column:
        table["sigma"] = np.full(len(table["force"]), display.to_display(sd, "extension"))
        units["sigma"] = "nm"
    if sd_t is not None:
        _add_torque(table, units, Ts, sd_t, sigma_column)
    prov = provenance(
        dna, simulated=True, noise=display.text(sd, "extension"),
        seed=seed if isinstance(seed, int)
        else None, turns_offset=[float(v) for v in n0],
        extension_offset=[display.text(v, "extension") for v in z0], thermal=thermal,
        model=m.name,
        interaction=inter.name,
        torque_noise=None if sd_t is None else display.text(sd_t, "torque"))
    return make_table(table, {k: units[k] for k in table}, prov)
