"""Synthetic magnetic-tweezers recordings, written in the real file formats.

Used by the tests, the example and as sample data. The beads follow a known hat
curve (:func:`supercoil.hat_curve`) at every plateau of a rotation schedule,
relax to each new extension with a first-order settling transient (time
constant ``settle_tau``), fluctuate with Ornstein-Uhlenbeck (exactly
discretised AR(1)) Brownian noise of standard deviation ``brownian`` and
correlation time ``correlation_time``, plus white tracking noise; all beads,
reference beads included, share a drift ``drift_rate * t + drift_amplitude *
sin(2 pi t / drift_period)``. The force follows the magnet height through a
**synthetic** calibration ``F = 20 pN exp(-h / 0.8 mm)`` (a made-up magnet,
written next to the recording as ``force_calibration.csv``; not a default of
the package).

:func:`write_synthetic_magscope` writes the MagScope layout and
:func:`write_synthetic_calisto` the CALISTO layouts described in
:mod:`supercoil.traces.magscope` and :mod:`supercoil.traces.calisto`.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd

from ..tables import make_table, provenance, write_csv
from ..units import U, as_turns, magnitude, ureg
from .trace import require_h5py

__all__ = ["SyntheticRecording", "simulate_recording", "synthetic_calibration",
           "write_synthetic_calisto", "write_synthetic_magscope"]

_F0_PN, _LAMBDA_MM = 20.0, 0.8  # the synthetic magnet: F = F0 exp(-h / lambda)
_EPOCH_NS = 1_764_547_200_000_000_000  # 2025-12-01 00:00 UTC, start of the recordings


def synthetic_calibration():
    """The synthetic magnet's calibration table: ``height`` [mm] -> ``force`` [pN]."""
    h = np.linspace(0.5, 5.0, 46)
    return make_table({"height": h, "force": _F0_PN * np.exp(-h / _LAMBDA_MM)},
                      {"height": "mm", "force": "pN"},
                      provenance(synthetic=True, model="F = 20 pN exp(-h / 0.8 mm)"))


def _height_of(force_pn):
    return _LAMBDA_MM * np.log(_F0_PN / np.asarray(force_pn, dtype=float))


class SyntheticRecording(NamedTuple):
    """A simulated recording (display units: s, nm, turns, mm) and its truth."""

    time: np.ndarray  # (n_frames,) s since the first frame
    beads: list  # labels: molecules "0".."m-1", then the reference beads
    reference_beads: list
    xyz: np.ndarray  # (n_frames, n_beads, 3) nm
    log_time: np.ndarray  # motor log times, s since the first frame
    log_turns: np.ndarray
    log_height: np.ndarray  # mm
    truth: pd.DataFrame  # molecule, plateau, force [pN], turns, extension [nm] (hat only)
    offsets: dict  # bead -> (turns_offset, surface z [nm])
    mean_drift: float  # nm, mean of the drift over the frames
    path: Path | None = None  # where a writer put it
    motor_path: Path | None = None


def _schedule(forces_pn, turns_grid, dwell, move):
    """Plateau states and the piecewise-linear magnet path (times relative to t=0)."""
    states = [(f, n) for f, grid in zip(forces_pn, turns_grid, strict=True) for n in grid]
    knots_t, knots_n, knots_h = [0.0], [states[0][1]], [_height_of(states[0][0])]
    plateaus = []
    t = 0.0
    for k, (f, n) in enumerate(states):
        h = float(_height_of(f))
        if k:
            t += move
            knots_t.append(t)
            knots_n.append(n)
            knots_h.append(h)
        plateaus.append((t, t + dwell, f, n, h))
        t += dwell
        knots_t.append(t)
        knots_n.append(n)
        knots_h.append(h)
    return plateaus, np.array(knots_t), np.array(knots_n), np.array(knots_h)


def _first_order(x, c, y0=0.0, block=64):
    """The recursion ``y_i = c y_(i-1) + x_i`` (``y_(-1) = y0``), exactly, in blocks.

    Within a block it is a product with the lower-triangular matrix ``c**(i-j)``; the last
    value is carried to the next block (numpy only: scipy.signal is slow to import).
    """
    k = np.arange(block)
    tri = np.tril(c ** np.maximum(k[:, None] - k[None, :], 0).astype(float))
    pw = c ** (k + 1.0)
    y = np.empty(x.size)
    carry = y0
    for a in range(0, x.size, block):
        seg = x[a:a + block]
        out = tri[: seg.size, : seg.size] @ seg + pw[: seg.size] * carry
        y[a:a + block] = out
        carry = out[-1]
    return y


def _ou(rng, n, sd, phi):
    """Stationary AR(1) (an exactly sampled Ornstein-Uhlenbeck process) of std ``sd``."""
    e = rng.normal(0.0, sd * np.sqrt(1.0 - phi**2), n)
    e[0] = rng.normal(0.0, sd)
    return _first_order(e, phi)


def simulate_recording(dna=None, forces=(0.4, 0.7) * ureg.pN, turns=None, *, molecules=2,
                       reference=1, points_per_force=9, dwell=5.0 * ureg.s,
                       move=0.5 * ureg.s, frame_rate=60.0 * ureg.Hz,
                       settle_tau=0.15 * ureg.s, brownian=10.0 * ureg.nm,
                       correlation_time=0.02 * ureg.s, tracking_noise=2.0 * ureg.nm,
                       drift_rate=1.0 * ureg.nm / ureg.s, drift_amplitude=20.0 * ureg.nm,
                       drift_period=60.0 * ureg.s, turns_offsets=None, surfaces=None,
                       seed=0, model="li-zhao") -> SyntheticRecording:
    """Simulate a rotation-curve recording (see the module docstring).

    Parameters
    ----------
    dna : DNA, optional
        True parameters (default: the ``dna`` parameter set).
    forces : Quantity [force]
        One rotation sweep per force (magnet heights from the synthetic calibration).
    turns : array-like, optional
        Turns of every sweep; default ``points_per_force`` values evenly over
        +-0.9 x :func:`supercoil.dna.fitting.fit.valid_turns_range` at each force.
    molecules, reference : int
        Numbers of tethered and of reference beads.
    turns_offsets, surfaces : sequence, optional
        Per molecule: turns offset (turns) and surface z (Quantity [length]);
        default: random in +-0.5 turn and 50-150 nm.
    model : str or DNAModel
        The hat-curve model the beads follow (:func:`supercoil.hat_curve`'s ``model``).
    """
    from ..dna.fitting.fit import valid_turns_range
    from ..parameters import load_parameters

    rng = np.random.default_rng(seed)
    dna = dna or load_parameters("dna")
    f_pn = np.atleast_1d(np.asarray(magnitude(forces, U.pN, "forces"), dtype=float))
    if turns is None:
        nmax = valid_turns_range(dna, ureg.Quantity(f_pn, "pN"))
        grids = [np.round(np.linspace(-0.9 * m, 0.9 * m, points_per_force), 2) for m in nmax]
    else:
        grids = [np.asarray(as_turns(turns, "turns"), dtype=float)] * f_pn.size
    dt = 1.0 / float(magnitude(frame_rate, U.s**-1, "frame_rate"))
    tw, tm = float(magnitude(dwell, U.s, "dwell")), float(magnitude(move, U.s, "move"))
    plateaus, kt, kn, kh = _schedule(f_pn, grids, tw, tm)
    time = np.arange(0.0, kt[-1], dt)
    n0 = rng.uniform(-0.5, 0.5, molecules) if turns_offsets is None else \
        np.asarray(turns_offsets, dtype=float)
    zs = rng.uniform(50, 150, molecules) if surfaces is None else \
        np.asarray(magnitude(surfaces, U.nm, "surfaces"), dtype=float)
    noise = (float(magnitude(brownian, U.nm, "brownian")),
             float(magnitude(tracking_noise, U.nm, "tracking_noise")),
             np.exp(-dt / float(magnitude(correlation_time, U.s, "correlation_time"))),
             1.0 - np.exp(-dt / float(magnitude(settle_tau, U.s, "settle_tau"))))
    drift = (float(magnitude(drift_rate, U.nm / U.s, "drift_rate")) * time
             + float(magnitude(drift_amplitude, U.nm, "drift_amplitude"))
             * np.sin(2 * np.pi * time / float(magnitude(drift_period, U.s, "drift_period"))))
    beads = [str(i) for i in range(molecules + reference)]
    xyz, truth = _simulate_beads(rng, (dna, model), time, plateaus, f_pn, n0, zs, drift, noise,
                                 molecules, len(beads))
    # the motor is polled every 50 ms (MagScope's Zaber managers), at a random phase: a move
    # or an arrival is logged up to 50 ms late; the state at t = 0 is written at connect
    log_t = np.concatenate([[0.0], rng.uniform(0.0, 0.05) + np.arange(0.0, kt[-1], 0.05)])
    return SyntheticRecording(
        time=time, beads=beads, reference_beads=beads[molecules:], xyz=xyz, log_time=log_t,
        log_turns=np.interp(log_t, kt, kn), log_height=np.interp(log_t, kt, kh),
        truth=truth,
        offsets={str(m): (float(n0[m]), float(zs[m])) for m in range(molecules)},
        mean_drift=float(drift.mean()))


def _simulate_beads(rng, dna, time, plateaus, f_pn, n0, zs, drift, noise, molecules, n_beads):
    """Bead positions (frames x beads x 3, nm) and the true plateau extensions."""
    from ..dna.hat import hat_curve

    sd_b, sd_t, phi, a = noise
    dna, model = dna
    n_fr = time.size
    xyz = np.empty((n_fr, n_beads, 3))
    truth = {"molecule": [], "plateau": [], "force": [], "turns": [], "extension": []}
    starts = np.array([p[0] for p in plateaus])
    which = np.clip(np.searchsorted(starts, time, side="right") - 1, 0, len(plateaus) - 1)
    for m in range(molecules):
        ext = np.empty(len(plateaus))
        for f in f_pn:
            idx = [k for k, p in enumerate(plateaus) if p[2] == f]
            hc = hat_curve(dna, f * ureg.pN, np.array([plateaus[k][3] for k in idx]) - n0[m],
                           model=model)
            ext[idx] = hc["extension"].to_numpy()
        for k, p in enumerate(plateaus):
            for key, v in (("molecule", str(m)), ("plateau", k), ("force", p[2]),
                           ("turns", p[3]), ("extension", ext[k])):
                truth[key].append(v)
        target = ext[which]
        # first-order settling towards the plateau's extension: y_i = y_(i-1) + a (x_i - y_(i-1))
        y = _first_order(a * target, 1.0 - a, y0=target[0])
        xyz[:, m, 2] = zs[m] + y + drift + _ou(rng, n_fr, sd_b, phi) + rng.normal(0, sd_t, n_fr)
        for c in (0, 1):
            xyz[:, m, c] = rng.uniform(-2e4, 2e4) + drift + _ou(rng, n_fr, 3 * sd_b, phi)
    for r in range(molecules, n_beads):
        xyz[:, r, 2] = rng.uniform(-50, 50) + drift + rng.normal(0, sd_t, n_fr)
        for c in (0, 1):
            xyz[:, r, c] = rng.uniform(-2e4, 2e4) + drift + rng.normal(0, sd_t, n_fr)
    return xyz, pd.DataFrame(truth)


def _motor_rows(log_t, values, origin_s):
    """Rows of a Zaber manager log: time, position, target, speed, busy, ... (21 columns)."""
    rows = np.full((log_t.size, 21), np.nan)
    rows[:, 0] = origin_s + log_t
    rows[:, 1] = values
    rows[:, 2] = values
    rows[:, 3] = 1.0
    rows[:, 4] = np.append(np.diff(values) != 0, False).astype(float)
    rows[:, 5] = 1.0
    return rows


def write_synthetic_magscope(folder, recording=None, *, batch=64, **kwargs) -> SyntheticRecording:
    """Write a synthetic MagScope acquisition folder; return the recording with its path.

    Writes ``Tracking Data 2025-12-01 00-00-00.000000.h5`` (group ``/tracking``;
    frames written in shuffled batches of ``batch`` frames, as MagScope's parallel
    processors may), ``ZaberNmsMotor.txt`` (rotation, turns), ``ZaberLsqMotor.txt``
    (height, mm) and ``force_calibration.csv``. ``recording`` (from
    :func:`simulate_recording`) or ``kwargs`` for it.
    """
    h5py = require_h5py(folder)
    rec = recording or simulate_recording(**kwargs)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    n_fr, n_b = rec.xyz.shape[:2]
    ts = _EPOCH_NS + np.rint(rec.time * 1e9).astype(np.uint64)
    order = np.arange(n_fr)
    chunks = np.array_split(order, max(1, n_fr // batch))
    np.random.default_rng(1).shuffle(chunks)
    order = np.concatenate(chunks)
    path = folder / "Tracking Data 2025-12-01 00-00-00.000000.h5"
    with h5py.File(path, "w") as fh:
        g = fh.create_group("tracking")
        g.attrs["schema_version"] = 1
        g.attrs["include_roi_positions"] = np.uint8(0)
        g.attrs["record_order"] = "writer_append_order"
        g.attrs["min_frame_timestamp_ns"] = np.uint64(ts.min())
        g.attrs["max_frame_timestamp_ns"] = np.uint64(ts.max())
        g.create_dataset("frame_timestamps_ns", data=ts[order], dtype=np.uint64)
        g.create_dataset("frame_offsets", data=np.arange(0, (n_fr + 1) * n_b, n_b,
                                                         dtype=np.uint64))
        g.create_dataset("bead_ids", data=np.tile(np.arange(n_b, dtype=np.uint16), n_fr))
        g.create_dataset("positions_nm", data=rec.xyz[order].reshape(-1, 3), dtype=np.float64)
    origin = _EPOCH_NS / 1e9
    header = "# timestamp " + " ".join(f"value_{i}" for i in range(1, 21))
    for name, vals in (("ZaberNmsMotor.txt", rec.log_turns), ("ZaberLsqMotor.txt",
                                                              rec.log_height)):
        np.savetxt(folder / name, _motor_rows(rec.log_time, vals, origin), header=header[2:])
    write_csv(synthetic_calibration(), folder / "force_calibration.csv")
    return rec._replace(path=path)


def write_synthetic_calisto(path, recording=None, *, text=False, **kwargs) -> SyntheticRecording:
    """Write a synthetic CALISTO recording: HDF5 at ``path``, or (``text=True``) the
    headerless bead file at ``path`` and the motor file ``<stem>_motor.txt`` beside it.

    Reference beads are the ``R<i>`` groups of the HDF5 file; in text they are
    the last bead columns (CALISTO text does not mark them). Also writes
    ``force_calibration.csv`` in the same folder.
    """
    rec = recording or simulate_recording(**kwargs)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_csv(synthetic_calibration(), path.parent / "force_calibration.csv")
    n_fr = rec.time.size
    t_motor = np.arange(0.0, rec.time[-1] + 0.05, 0.05)
    turns = np.interp(t_motor, rec.log_time, rec.log_turns)
    height = np.interp(t_motor, rec.log_time, rec.log_height)
    if text:
        beads = np.column_stack([np.arange(n_fr), rec.time, rec.xyz.reshape(n_fr, -1)])
        np.savetxt(path, beads, fmt="%.6f")
        motor_path = path.with_name(path.stem + "_motor.txt")
        np.savetxt(motor_path, np.column_stack([np.arange(t_motor.size), t_motor, height, turns]),
                   fmt="%.6f")
        return rec._replace(path=path, motor_path=motor_path)
    h5py = require_h5py(path)
    with h5py.File(path, "w") as fh:
        fh.create_dataset("timestamp", data=rec.time)
        st = fh.create_group("stage")
        st.create_dataset("t_s", data=t_motor)
        st.create_dataset("mag_pos_mm", data=height)
        st.create_dataset("mag_rot_turn", data=turns)
        for j, lab in enumerate(rec.beads):
            g = fh.create_group(("R" if lab in rec.reference_beads else "M") + lab)
            for c, name in enumerate(("x_nm", "y_nm", "z_nm")):
                g.create_dataset(name, data=rec.xyz[:, j, c])
    return rec._replace(path=path, motor_path=None)
