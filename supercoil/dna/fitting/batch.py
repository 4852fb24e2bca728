"""Per-molecule fits of a large table: :func:`fit_many` (serial or on any executor).

The table is checked and converted to SI once and the arguments are validated
once (a template :class:`~supercoil.dna.fitting.fit.FitSpec`); the rows are
split by molecule once (one stable sort, :meth:`RotationData.groups`). Each
task (:class:`MoleculeTask`) holds only its molecule's slice and the shared
settings; a process pool or a dask client gets them in chunks (one round trip
for several molecules), each submitted as soon as it is ready; the worker fits
and builds the molecule's table row, so the client only stacks rows (its cost
per molecule: :mod:`supercoil.benchmark.fit_many`). A worker process limits BLAS
to one thread (:mod:`threadpoolctl`) for the duration of its fit only, and only
for a molecule large enough that BLAS would run threaded (:data:`BLAS_LIMIT_FROM`).
"""

from __future__ import annotations

import dataclasses
import os
from concurrent.futures import Future, ProcessPoolExecutor, as_completed

import numpy as np

from supercoil import display
from supercoil.dna.fitting.data import RotationData
from supercoil.dna.fitting.fit import emit, run_fit
from supercoil.dna.fitting.options import DEFAULTS, FitOptions, FitSpec
from supercoil.dna.fitting.prepare import prepare, strip_molecule_keys
from supercoil.dna.fitting.progress import Progress
from supercoil.dna.fitting.weights import checked_sigma
from supercoil.dna.validity import check_dna
from supercoil.exceptions import FitError
from supercoil.tables import make_table, provenance

__all__ = ["fit_many"]


@dataclasses.dataclass
class MoleculeTask:
    """What a worker gets: one molecule's points (SI arrays) and the shared fit settings.

    ``settings`` is the :class:`~supercoil.dna.fitting.fit.FitSpec` validated
    once on the whole table (its parameters are copied on the worker); with a
    dask client it is None here: the settings are scattered once and their
    future is a separate argument of the task (dask resolves only top-level
    futures).
    """

    label: str
    data: RotationData
    settings: FitSpec | None
    row: dict  # names, display factors and units of the table columns


_CONTROLLER = []

#: Jacobians (residuals x free parameters; a torque channel doubles the residuals) from
#: this size on are fitted with BLAS limited to one thread in a worker process. Below it
#: no BLAS call of a fit runs threaded: in forked workers (OpenBLAS 0.3.30/0.3.31, 2 cores)
#: the first BLAS thread appeared at 3,600-4,200 points with 3 free parameters,
#: 2,640-2,730 with 4 and 1,800-2,100 with 5 (9,000-11,000 entries; OpenBLAS runs gemv
#: threaded from 2304 x 4 = 9,216). Limiting is not free in a fresh worker: its first
#: ``openblas_set_num_threads`` starts the BLAS threads, which then spin on the CPU for a
#: while (measured: 3 threads instead of 1, each spinning while idle), competing with the
#: fits (the pool's speed-up on 2 workers fell from about 1.8x to 1.7x).
BLAS_LIMIT_FROM = 8192


def _controller():
    """This process's threadpoolctl controller, made once: the library scan of a fresh
    ``threadpool_limits`` costs about half a fit, a cached controller's limit 1/60 of
    that."""
    if not _CONTROLLER:
        try:
            from threadpoolctl import ThreadpoolController
        except ImportError:  # not a dependency: without it BLAS keeps its threads
            _CONTROLLER.append(None)
        else:
            _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0]


def _fit_worker(task, parent_pid=None, settings=None):
    """Module-level (picklable) worker of :func:`fit_many`: builds the molecule's table row.

    ``settings`` replaces ``task.settings`` (a dask client passes the scattered
    settings here). Never raises: a failure is the row's ``error``. Returns
    ``(row, warning records)``.
    """
    try:
        settings = task.settings if settings is None else settings
        spec = dataclasses.replace(settings, data=task.data, params=settings.params.copy())
        n_free = len(spec.params.free)
        if spec.data.n - n_free <= 0:
            raise FitError(f"{spec.data.n} data points cannot determine {n_free} free "
                           "parameters")
        worker = parent_pid not in (None, os.getpid())
        rows = spec.data.n * (2 if spec.data.has_torque else 1)  # residuals: z (and torque)
        big = rows * n_free >= BLAS_LIMIT_FROM
        controller = _controller() if worker and big else None
        if controller is not None:
            with controller.limit(limits=1):
                solution = run_fit(spec)
        else:  # serial, a thread, or too small to use BLAS threads: leave them alone
            solution = run_fit(spec)
    except Exception as exc:  # reported per molecule, not raised for the batch
        return _row(task, None, f"{type(exc).__name__}: {exc}"), []
    return _row(task, solution, ""), solution.warnings


def _row(task, solution, error):
    """The table row of one molecule (the worker builds it; the client only stacks rows)."""
    layout = task.row
    ok = solution is not None
    row = {"molecule": task.label, "success": ok, "determined": ok and not np.any(
        solution.undetermined), "error": error, "ndata": int(task.data.n),
        # dimensionless, as FitResult.redchi (1 by construction with unit weights); the noise
        # estimate itself is the residual RMS of the extensions (nm)
        "reduced_chi_square": float(solution.redchi) if ok else np.nan,
        "residual_rms": (display.to_display(solution.channels["extension"]["rms"], "extension")
                         if ok else np.nan),
        "nfev": int(solution.nfev) if ok else 0}
    by_name = {n: j for j, n in enumerate(solution.names)} if ok else {}
    for name, factor in layout["factors"].items():
        j = by_name.get(name)
        row[name] = np.nan if j is None else float(solution.values[j] * factor)
        row[f"{name}_stderr"] = np.nan if j is None else float(solution.stderr[j] * factor)
    if layout["torque"]:
        row["torque_residual_rms"] = (
            display.to_display(solution.channels["torque"]["rms"], "torque") if ok
            else np.nan)
    row["warnings"] = "; ".join(m for _, m in solution.warnings) if ok else ""
    return row


def _layout(template):
    """Column names, display factors and units of the result table (from the template)."""
    names = list(template.params.free)
    units = {k: "" for k in ("molecule", "success", "determined", "error", "ndata",
                             "reduced_chi_square", "residual_rms", "nfev")}
    units["residual_rms"] = "nm"
    for name in names:
        units[name] = units[f"{name}_stderr"] = template.params[name].unit
    torque = template.data.has_torque
    if torque:
        units["torque_residual_rms"] = "pN*nm"
    units["warnings"] = ""
    return {"factors": {n: template.params[n].factor for n in names}, "units": units,
            "torque": torque}


def _table(rows, layout, template, dna, options):
    cols = {k: [r[k] for r in rows] for k in layout["units"]}
    prov = provenance(dna, vary=list(template.vary), thermal=template.thermal,
                      weighting=template.data.weighting, model=template.model.name,
                      interaction=template.interaction.name, **options)
    return make_table(cols, dict(layout["units"]), prov)


def _is_dask_client(executor):
    return hasattr(executor, "scatter") and hasattr(executor, "gather") and hasattr(
        executor, "get_executor")


def _completed(pending, executor):
    """The submitted futures as they complete (any executor's futures)."""
    futs = list(pending)
    if futs and all(isinstance(f, Future) for f in futs):
        return as_completed(futs)
    if _is_dask_client(executor):
        from distributed import as_completed as dask_as_completed

        return dask_as_completed(futs)
    return futs  # other futures with .result(): in submission order


def _fit_chunk(tasks, parent_pid=None, settings=None):
    """Several molecules in one task (a process pool or a dask client): one round trip."""
    return [_fit_worker(t, parent_pid, settings) for t in tasks]


def _chunk_size(n_molecules):
    """Molecules per dask task: 1 up to 64 molecules, then up to 16 (>= 4 tasks per 64)."""
    return max(1, min(16, n_molecules // 64))


#: most molecules in one submit to a process pool, and the share of the molecules not yet
#: submitted that one submit may take (1/8: the last submits carry single molecules).
#: Measured (200 molecules of 330 points, ProcessPoolExecutor(2), medians of 3): the
#: parent's CPU per molecule falls by 25 / 32 / 40 % from one molecule per submit with
#: chunks of up to 2 / 4 / 8 (1/16 of the rest). With fast fits (the plectoneme start
#: tables cached) the parent's share shows in the wall time: speed-up over serial
#: 1.76-1.77x with (4, 1/16) against 1.81-1.83x with (16, 1/8), the parent's CPU per
#: molecule 20-25 % lower (alternating runs).
POOL_CHUNK, POOL_TAIL = 16, 8


def _chunk_sizes(n_molecules, executor):
    """Molecules per submit, in submission order.

    A :class:`~concurrent.futures.ProcessPoolExecutor`: up to :data:`POOL_CHUNK`
    molecules, but at most 1/:data:`POOL_TAIL` of those not yet submitted, so
    the tail is single molecules and the workers finish together. A dask
    client: :func:`_chunk_size`. Any other executor: one molecule per submit.
    """
    if _is_dask_client(executor):
        k = _chunk_size(n_molecules)
        return [min(k, n_molecules - i) for i in range(0, n_molecules, k)]
    if not isinstance(executor, ProcessPoolExecutor):
        return [1] * n_molecules
    sizes, left = [], n_molecules
    while left > 0:
        sizes.append(max(1, min(POOL_CHUNK, left // POOL_TAIL)))
        left -= sizes[-1]
    return sizes


def _check_executor(executor):
    """TypeError naming ``executor`` unless it is None or has a callable ``submit``."""
    if executor is None or callable(getattr(executor, "submit", None)):
        return
    hint = (" (a name is not an executor: pass e.g. concurrent.futures.ProcessPoolExecutor())"
            if isinstance(executor, str) else "")
    raise TypeError("executor must be None, a concurrent.futures.Executor or a "
                    "dask.distributed.Client (an object with submit(fn, *args)), got "
                    f"{type(executor).__name__}{hint}")


def _future(fut, pending):
    """``fut`` if it is a new future with ``result()``; else TypeError naming the executor.

    An executor whose ``submit`` returned None (or one object for two submits)
    lost every task but one under a single key: a bare KeyError at the end.
    """
    if not callable(getattr(fut, "result", None)):
        raise TypeError(f"executor.submit() returned {type(fut).__name__}, not a future "
                        "with a result() method")
    try:
        seen = fut in pending
    except TypeError:  # unhashable
        raise TypeError(f"executor.submit() returned an unhashable {type(fut).__name__}; "
                        "fit_many keys its tasks by future") from None
    if seen:
        raise TypeError("executor.submit() returned the same future for two tasks")
    return fut


def _collect(pending, executor, finished):
    """Results of the submitted fits as they complete (``finished(label, row, records)``).

    ``pending`` maps a future to its task, or to a list of tasks (a chunk).
    """
    for fut in _completed(pending, executor):
        tasks = pending[fut]
        chunk = isinstance(tasks, list)
        tasks = tasks if chunk else [tasks]
        try:
            results = fut.result() if chunk else [fut.result()]
        except Exception as exc:  # the executor itself failed (e.g. a worker died)
            results = [(_row(t, None, f"{type(exc).__name__}: {exc}"), []) for t in tasks]
        for task, (row, records) in zip(tasks, results, strict=True):
            finished(task.label, row, records)


def fit_many(data, dna, vary=DEFAULTS.vary, fixed=DEFAULTS.fixed, bounds=DEFAULTS.bounds, *,
             start=DEFAULTS.start, sigma=DEFAULTS.sigma,
             fit_turns_offset=DEFAULTS.fit_turns_offset,
             fit_extension_offset=DEFAULTS.fit_extension_offset, thermal=DEFAULTS.thermal,
             max_nfev=DEFAULTS.max_nfev, tol=DEFAULTS.tol, model=DEFAULTS.model,
             interaction=DEFAULTS.interaction, executor=None, progress=None):
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
    executor : concurrent.futures.Executor or dask.distributed.Client, optional
        Runs the fits in parallel (``ProcessPoolExecutor``, ``ThreadPoolExecutor``,
        ``client.get_executor()`` or a ``dask.distributed.Client`` itself): each
        ``submit`` of a module-level function carries some molecules' points
        only and the fit settings (SI floats and numpy arrays, no pint or
        pandas objects); the worker fits and builds each molecule's table row.
        A ``ProcessPoolExecutor`` gets chunks of up to :data:`POOL_CHUNK`
        molecules, single molecules at the end, a dask
        client chunks of up to 16, the settings once per worker (``scatter``)
        and the tasks with ``pure=False``; any other executor one molecule per
        ``submit``. Each chunk is submitted as soon as it is built; results
        and progress are per molecule. None: serial. Anything without a
        ``submit``, or a ``submit`` not returning a new future with
        ``result()``, is a TypeError naming the executor.
    progress : None, bool, "log" or callable
        None (default): a :mod:`tqdm.auto` bar on stderr when stderr is a
        terminal or a notebook's output, else silent; ``"log"``: also one line
        per finished molecule off a terminal (``molecule m3 done (3/20)``);
        False: silent; True: always the bar (tqdm installed); a callable:
        ``progress(done, total, molecule)`` after each molecule finishes.

    Returns
    -------
    pandas.DataFrame
        Package table convention, one row per molecule in order of first
        appearance: ``molecule``, ``success`` (the fit ran and converged),
        ``determined`` (False when the data of that molecule do not determine
        some free parameter: its ``<name>_stderr`` is inf; also False for a
        failed fit), ``error`` (the exception for a failed fit, else ""),
        ``ndata``, ``reduced_chi_square`` (dimensionless, as
        :attr:`FitResult.redchi`: 1 by construction with unit weights, the
        chi-square per degree of freedom with sigmas), ``residual_rms`` (nm,
        the extension residual RMS: with unit weights the noise estimate by
        which the errors are scaled), ``nfev``, then ``<name>`` and
        ``<name>_stderr`` for every varied parameter and offset (NaN where the
        fit failed), ``warnings``. Warnings of single fits are also re-issued,
        prefixed by the molecule.

    Raises
    ------
    DataError, FitError, ModelError
        Only for problems common to all molecules (malformed table, unknown
        parameter names); failures of single fits are reported in the table.
    """
    check_dna(dna)
    _check_executor(executor)
    fixed, bounds, start = (strip_molecule_keys(d, name) for d, name in
                            ((fixed, "fixed"), (bounds, "bounds"), (start, "start")))
    whole = RotationData.from_frame(data)
    if sigma is not None:
        whole = whole.with_sigma(checked_sigma(sigma, whole))  # converted once; split by rows
    # validate the arguments once on the whole table as one molecule (names, units, vary):
    # the settings every worker gets (SI floats, no pint objects)
    options = FitOptions(vary, fixed, bounds, start, None, fit_turns_offset,
                         fit_extension_offset, thermal, max_nfev, tol, model, interaction)
    template = prepare(None, dna, options, rotation=whole.take(np.arange(whole.n), "all"))
    layout = _layout(template)
    labels = list(whole.labels)
    bar = Progress(progress, len(labels))
    rows = {}

    def finished(lab, row, records):
        rows[lab] = row
        if row["success"]:
            emit(records, prefix=f"molecule {lab}: ", stacklevel=4)
        bar.update(lab)

    # the settings without the template's data (the whole table): each task has its rows
    settings, args, extra = dataclasses.replace(template, data=None), (), {}
    if _is_dask_client(executor):  # one copy of the settings per worker, not one per task
        args, extra = (executor.scatter(settings, broadcast=True, hash=False),), {"pure": False}
        settings = None
    pending, pid = {}, os.getpid()
    tasks = (MoleculeTask(lab, whole.take(index, lab), settings, layout)
             for lab, index in zip(labels, whole.groups(), strict=True))
    try:
        if executor is None:
            for task in tasks:
                finished(task.label, *_fit_worker(task))
        for k in _chunk_sizes(len(labels), executor) if executor is not None else ():
            chunk = [next(tasks) for _ in range(k)]  # submitted as soon as it is built
            if k == 1 and not args:
                pending[_future(executor.submit(_fit_worker, chunk[0], pid), pending)] = chunk[0]
            else:
                fut = executor.submit(_fit_chunk, chunk, pid, *args, **extra)
                pending[_future(fut, pending)] = chunk
        _collect(pending, executor, finished)
    finally:
        bar.close()
    options = {"fixed": {k: str(v) for k, v in (fixed or {}).items()},
               "bounds": {k: [str(x) for x in v] for k, v in (bounds or {}).items()}}
    return _table([rows[lab] for lab in labels], layout, template, dna, options)
