"""Per-molecule fits of a large table: :func:`fit_many` (serial or on any executor).

The table is checked and converted to SI once; its rows are split by molecule
once (one stable sort, :meth:`RotationData.groups`); each molecule's spec holds
only its own slice (no copy of the table or of its ``attrs``) and is submitted
as soon as it is ready. A worker process limits BLAS to one thread
(:mod:`threadpoolctl`) for the duration of its fit only.
"""

from __future__ import annotations

import os
from concurrent.futures import Future, as_completed

import numpy as np

from supercoil.dna.fitting.data import RotationData
from supercoil.dna.fitting.fit import DEFAULT_VARY, emit, prepare, run_fit
from supercoil.dna.fitting.prepare import strip_molecule_keys
from supercoil.dna.interactions import DEFAULT_INTERACTION
from supercoil.dna.models import DEFAULT_MODEL
from supercoil.exceptions import SupercoilError
from supercoil.tables import make_table, provenance

__all__ = ["fit_many"]

_KEEP = ("names", "values", "stderr", "reduced_chi_square", "ndata", "nfree", "nfev",
         "warnings", "seconds", "n0", "z0", "undetermined")


def _fit_worker(spec, parent_pid=None):
    """Module-level (picklable) worker of :func:`fit_many`: never raises."""
    try:
        if parent_pid is not None and os.getpid() != parent_pid:
            from threadpoolctl import threadpool_limits

            with threadpool_limits(limits=1):
                core = run_fit(spec)
        else:  # serial or a thread: do not change the process-wide BLAS threads
            core = run_fit(spec)
    except Exception as exc:  # reported per molecule, not raised for the batch
        return {"ok": False, "error": f"{type(exc).__name__}: {exc}"}
    return {"ok": True, **{k: core[k] for k in _KEEP}}


def _sigma_slice(sigma, index):
    if sigma is None:
        return None
    if np.ndim(getattr(sigma, "magnitude", sigma)):
        return sigma[index]
    return sigma


def _table(labels, results, template, ndata, dna, options):
    names = list(template.params.free)
    cols = {k: [] for k in ("molecule", "success", "determined", "error", "ndata",
                            "reduced_chi_square", "nfev")}
    units = dict.fromkeys(cols, "")
    for name in names:
        cols[name], cols[f"{name}_stderr"] = [], []
        units[name] = units[f"{name}_stderr"] = template.params[name].unit
    cols["warnings"], units["warnings"] = [], ""
    factors = {n: template.params[n].factor for n in names}
    for lab in labels:
        res = results[lab]
        ok = bool(res["ok"])
        cols["molecule"].append(lab)
        cols["success"].append(ok)
        cols["error"].append("" if ok else res["error"])
        cols["determined"].append(ok and not np.any(res.get("undetermined", [])))
        cols["ndata"].append(int(res["ndata"]) if ok else ndata[lab])
        cols["reduced_chi_square"].append(float(res["reduced_chi_square"]) if ok else np.nan)
        cols["nfev"].append(int(res["nfev"]) if ok else 0)
        by_name = dict(zip(res.get("names", []), range(len(res.get("names", []))), strict=True))
        for name in names:
            j = by_name.get(name)
            cols[name].append(np.nan if j is None else res["values"][j] * factors[name])
            cols[f"{name}_stderr"].append(np.nan if j is None
                                          else res["stderr"][j] * factors[name])
        cols["warnings"].append("; ".join(m for _, m in res["warnings"]) if ok else "")
        if ok:
            emit(res["warnings"], prefix=f"molecule {lab}: ")
    prov = provenance(dna, vary=list(template.vary), thermal=template.thermal,
                      weighting=template.data.weighting, model=template.model.name,
                      interaction=template.interaction.name, **options)
    return make_table(cols, units, prov)


def _collect(pending, finished):
    """Results of the submitted fits as they complete (``finished(label, result)``)."""
    order = as_completed(pending) if all(isinstance(f, Future) for f in pending) else list(
        pending)  # e.g. a dask.distributed Client used directly: not cf.Futures
    for fut in order:
        try:
            res = fut.result()
        except Exception as exc:  # the executor itself failed (e.g. a worker died)
            res = {"ok": False, "error": f"{type(exc).__name__}: {exc}"}
        finished(pending[fut], res)


def fit_many(data, dna, vary=DEFAULT_VARY, fixed=None, bounds=None, *, start=None, sigma=None,
             fit_turns_offset=True, fit_extension_offset=True, thermal=True, max_nfev=None,
             tol=1e-10, model=DEFAULT_MODEL, interaction=DEFAULT_INTERACTION, executor=None,
             progress=None):
    """Fit every molecule of ``data`` separately; one result row per molecule.

    Parameters
    ----------
    data : pandas.DataFrame
        As for :func:`fit_hat_curves`, with a ``molecule`` column (without it
        the whole table is one molecule).
    dna, vary, fixed, bounds, start, sigma, fit_turns_offset, fit_extension_offset, thermal,
    max_nfev, tol, model, interaction
        As for :func:`fit_hat_curves` (offsets are named without the molecule
        suffix: ``"turns_offset"``; a per-point ``sigma`` is split by molecule).
    executor : concurrent.futures.Executor, optional
        Runs the fits in parallel (``ProcessPoolExecutor``, ``ThreadPoolExecutor``,
        ``dask.distributed.Client(...).get_executor()`` or the client itself):
        each molecule is one ``executor.submit`` of a module-level function with
        picklable arguments (SI floats, no pint objects). None: serial.
    progress : callable, optional
        ``progress(done, total, molecule)`` after each molecule finishes.

    Returns
    -------
    pandas.DataFrame
        Package table convention, one row per molecule in order of first
        appearance: ``molecule``, ``success`` (the fit ran and converged),
        ``determined`` (False when the data of that molecule do not determine
        some free parameter: its ``<name>_stderr`` is inf; also False for a
        failed fit), ``error`` (the exception for a failed fit, else ""),
        ``ndata``, ``reduced_chi_square``, ``nfev``, then ``<name>`` and
        ``<name>_stderr`` for every varied parameter and offset (NaN where the
        fit failed), ``warnings``. Warnings of single fits are also re-issued,
        prefixed by the molecule.

    Raises
    ------
    DataError, FitError, ModelError
        Only for problems common to all molecules (malformed table, unknown
        parameter names); failures of single fits are reported in the table.
    """
    fixed, bounds, start = (strip_molecule_keys(d) for d in (fixed, bounds, start))
    whole = RotationData.from_frame(data)
    kw = dict(vary=vary, fixed=fixed, bounds=bounds, start=start,
              fit_turns_offset=fit_turns_offset, fit_extension_offset=fit_extension_offset,
              thermal=thermal, max_nfev=max_nfev, tol=tol, model=model,
              interaction=interaction)
    groups = whole.groups()
    # validate the arguments once on the whole table as one molecule (names, units, vary)
    template = prepare(None, dna, sigma=sigma, rotation=whole.take(np.arange(whole.n), "all"),
                       **kw)
    labels = list(whole.labels)
    ndata = {lab: len(g) for lab, g in zip(labels, groups, strict=True)}
    results, pending, done = {}, {}, [0]

    def finished(lab, res):
        results[lab] = res
        done[0] += 1
        if progress is not None:
            progress(done[0], len(labels), lab)

    pid = os.getpid()
    for lab, index in zip(labels, groups, strict=True):
        rot = whole.take(index, lab)
        sig = _sigma_slice(sigma, index)
        try:
            spec = prepare(None, dna, sigma=sig, rotation=rot, **kw)
        except SupercoilError as exc:
            finished(lab, {"ok": False, "error": f"{type(exc).__name__}: {exc}"})
            continue
        if executor is None:
            finished(lab, _fit_worker(spec))
        else:
            pending[executor.submit(_fit_worker, spec, pid)] = lab
    _collect(pending, finished)
    options = {"fixed": {k: str(v) for k, v in (fixed or {}).items()},
               "bounds": {k: [str(x) for x in v] for k, v in (bounds or {}).items()}}
    return _table(labels, results, template, ndata, dna, options)

