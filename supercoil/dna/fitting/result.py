"""The result of a hat-curve fit (:class:`FitResult`): estimates, errors, tables."""

from __future__ import annotations

import functools
import math

import numpy as np
import pandas as pd

from supercoil import display
from supercoil.dna.fitting.fit_parameters import DNA_FIELDS
from supercoil.tables import make_table, provenance

__all__ = ["FitResult", "fmt_pm", "log_likelihood_term"]


def fmt_pm(v, e):
    """``value ± error`` with the error's significant digits; ``(not determined)`` for inf."""
    if np.isinf(e):
        return f"{v:.6g} (not determined)"
    if not np.isfinite(e) or e <= 0:
        return f"{v:.6g}"
    digits = max(0, 1 - math.floor(math.log10(e)))
    return f"{v:.{digits}f} ± {e:.{digits}f}" if digits < 12 else f"{v:.6g} ± {e:.2g}"


def _correlation(cov, undetermined):
    d = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    corr[~np.isfinite(corr)] = 0.0
    np.fill_diagonal(corr, 1.0)
    corr[undetermined, :] = np.nan
    corr[:, undetermined] = np.nan
    corr[undetermined, undetermined] = 1.0
    return corr



def log_likelihood_term(channels, sum_squares, ndata):
    """``N ln(chi2 / N)``, or its sum over the channels of a joint fit.

    The Gaussian log-likelihood (times -2, constants dropped) with the noise
    level of each channel profiled out, as lmfit's AIC and BIC use it:
    ``chi2`` is the sum of squared residuals weighted by the stated sigmas,
    or on the channel's fixed unit scale (1 nm, 1 pN nm) where the fit
    estimated the noise: the estimated noise itself differs between models and
    must not enter the criterion (with it every model's ``chi2`` would be ``N``).
    ``channels`` are the plain per-channel records of the fit core;
    ``sum_squares`` the extension-only fit's weighted sum (1 nm unit weights).
    """
    if "torque" not in channels:
        return ndata * math.log(sum_squares / ndata)
    total = 0.0
    for name, c in channels.items():
        n = c["n"]
        if c["noise"] is None:  # stated sigmas
            chi2 = c["chi_square"]
        else:  # sum of squares on the channel's fixed unit scale
            chi2 = display.to_display(c["rms"], name) ** 2 * c["dof"]
        total += n * math.log(chi2 / n)
    return total


def _channel_stats(channels):
    """Per-channel statistics with quantities (each channel in its own unit)."""
    out = {}
    for name, c in channels.items():
        out[name] = {
            "ndata": int(c["n"]), "chi_square": float(c["chi_square"]),
            "dof": float(c["dof"]), "weighting": c["weighting"],
            "residual_rms": display.quantity(c["rms"], name),
            "noise": None if c["noise"] is None else display.quantity(c["noise"], name),
        }
    return out


class FitResult:
    """The result of :func:`fit_hat_curves`.

    Attributes
    ----------
    parameters : dict of str -> pint.Quantity
        Best-fit values of the free parameters: the varied DNA fields (nm),
        model or interaction parameters (their declared unit) and the offsets
        ``turns_offset`` (turn) and ``extension_offset`` (nm); with a
        ``molecule`` column the offsets are named ``turns_offset[<molecule>]``.
        The canonical estimates (``parameters[name]`` is
        ``params[name].quantity()``, the same number).
    stderr : dict of str -> pint.Quantity
        One-sigma standard errors, same keys and units; ``inf`` for a
        parameter the data do not determine (see ``undetermined``).
    params : FitParameters
        All parameters (free and fixed) with values, errors, bounds and
        plausible limits (SI): lmfit's name, the set ``params=`` takes. Kept
        beside :attr:`parameters`, which holds the same estimates as
        quantities; read estimates from :attr:`parameters`.
    start : dict of str -> pint.Quantity
        The start values of the free parameters (given, or read from the data).
    undetermined : list of str
        Free parameters with a component in the numerical null space of the
        Jacobian: standard error ``inf``, NaN covariance and correlation rows
        and columns, and a :class:`~supercoil.exceptions.FitWarning`.
    fixed : dict of str -> pint.Quantity
        The parameters held fixed (DNA fields not varied, offsets switched off).
    covariance, correlation : pandas.DataFrame
        Of the free parameters in the units of ``parameters`` (``attrs["units"]``).
    chisqr, redchi : float
        lmfit's names: ``chisqr = sum(((model - data) / sigma)^2)``, always
        dimensionless, and ``redchi = chisqr / nfree``. With per-point sigmas
        the usual chi-square (``redchi`` near 1 when model and sigmas describe
        the data). With unit weights sigma is the noise estimate
        (:attr:`residual_rms`, the residual RMS), so ``chisqr == nfree`` and
        ``redchi == 1`` by construction: no goodness of fit (the report then
        shows the noise estimate and the runs test); the sum of squared
        residuals itself is :attr:`sum_squares`. A joint extension + torque
        fit sums both channels, each weighted by its sigmas or its own noise
        estimate (then ``chisqr`` is about ``nfree``; see :attr:`channels`).
    chi_square, reduced_chi_square : float
        The same numbers as ``chisqr`` and ``redchi`` (the package's older
        names). In releases up to 0.2 they were in nm^2 with unit weights.
    sum_squares : pint.Quantity
        ``sum((data - model)^2)`` of the extensions (nm^2).
    aic, bic : float
        Akaike and Bayesian information criteria as lmfit defines them,
        ``N ln(chi2 / N) + 2 k`` and ``N ln(chi2 / N) + ln(N) k``, with ``chi2``
        the weighted sum of squares on the stated sigmas or the fixed unit
        scale (1 nm, 1 pN nm; per channel in a joint fit, see
        :func:`log_likelihood_term`) and ``k`` = :attr:`n_determined`, the
        free parameters the data determine (undetermined ones are not
        counted). Only differences between fits of the same data mean anything.
    nvarys, n_determined : int
        Free parameters (offsets included), and those not in :attr:`undetermined`.
    x : numpy.ndarray
        The best-fit values of the free parameters in the order of
        :attr:`names`, in their display units (scipy's ``OptimizeResult.x``).
    jac : numpy.ndarray, shape (ndata, nvarys)
        Jacobian of the normalised residuals ``(model - data) / sigma`` (whose
        squares sum to ``chisqr``) with respect to :attr:`x` (display units),
        at the solution: ``inv(jac.T @ jac)`` is :attr:`covariance` when every
        parameter is determined.
    residual : numpy.ndarray
        The normalised residuals ``(model - data) / sigma`` (extensions, then
        torques); ``residual @ residual == chisqr``.
    success : bool
        The optimiser converged (scipy's ``status > 0``); ``message`` says how.
    residual_rms : pint.Quantity
        ``sqrt(sum((data - model)^2) / nfree)`` (nm) of the extensions (in a
        joint fit with the extension channel's share of ``nfree``): with unit
        weights the estimate of the extension noise, by which the errors are scaled.
    goodness : dict
        The goodness-of-fit test that applies (``"chi-square"`` with sigmas,
        ``"runs"`` with unit weights) and its ``p_value``.
    ndata, nfree, nfev : int
        Data points (extensions plus torques in a joint fit), degrees of
        freedom, model evaluations (of all re-solves in a joint fit).
    weighting : str
        ``"sigma column"``, ``"sigma argument"`` or ``"unit"``.
    residuals, best_fit : pint.Quantity
        ``data - model`` and the model extensions at the data points (nm).
    dna : DNA
        The input DNA with the fitted (global) fields replaced by their estimates.
    model, interaction
        The model and interaction instances with the fitted parameters.
    data : pandas.DataFrame
        The data as given.
    channels : dict of str -> dict
        Per fitted channel (``"extension"``, and ``"torque"`` with a torque
        column): ``ndata``, ``chi_square`` (that channel's weighted sum),
        ``dof`` (the degrees of freedom shared by point count), ``weighting``,
        ``residual_rms`` (Quantity, nm or pN nm) and ``noise`` (the channel's
        own noise estimate used as its sigma in a joint fit without sigmas,
        else None); docs/theory/fitting.md#joint-torque-fit.
    torque_best_fit, torque_residuals : pint.Quantity or None
        With a torque column: the model torque at the data points and
        ``data - model`` (pN nm); else None.
    njev, kernel_calls, kernel_failures : int
        Jacobian evaluations, calls of the model's kernel (residuals and
        Jacobians) and those that failed (a named model error at a trial point).
    seconds, cpu_seconds : float
        Wall-clock and CPU time of the fit (``time.process_time``).
    curve_cpu_seconds : float
        CPU time of one evaluation of the model at the data points with the
        best-fit parameters (measured by :func:`compare_models`; else NaN).
    vary : list of str
        The DNA, model and interaction parameters fitted (offsets not listed).
    solution : FitSolution
        What the fit engine returned (SI floats and arrays: best fit, offsets
        per molecule, phases, per-channel statistics, ...).
    spec : FitSpec
        The validated settings of the fit (``spec.data``: the data in SI).
    warnings : list of str
        Every warning of the fit (also in :meth:`report`); with their
        categories in :attr:`warning_records`.
    notes : list of str
        What the fit decided for the user (also in :meth:`report`): a default
        parameter the model does not use and so not varied, the channel that
        gave the turns-offset start, the length start read from the data.
    """

    def __init__(self, solution, spec, data, dna):
        self.solution = solution
        self.spec = spec
        self.data = data
        self.params = solution.params
        self.names = list(solution.names)
        free = [self.params[n] for n in self.names]
        self.parameters = {p.name: p.quantity(v) for p, v in zip(free, solution.values,
                                                                   strict=True)}
        self.stderr = {p.name: p.quantity(e) for p, e in zip(free, solution.stderr,
                                                             strict=True)}
        self.start = {p.name: p.quantity(v) for p, v in zip(free, solution.start, strict=True)}
        self.units = {p.name: p.unit for p in free}
        self.vary = list(spec.vary)
        factors = np.array([p.factor for p in free])
        self._cov = solution.covariance * np.outer(factors, factors)  # display units
        undetermined = np.asarray(solution.undetermined, dtype=bool)
        self._undetermined_mask = undetermined
        self.undetermined = [n for n, u in zip(self.names, undetermined, strict=True) if u]
        self.chisqr = self.chi_square = float(solution.chisqr)
        self.redchi = self.reduced_chi_square = float(solution.redchi)
        resid = spec.data.extension - solution.best_fit
        self.sum_squares = display.quantity(float(resid @ resid), "sum_squares")
        self.nfree = int(solution.nfree)
        self.nvarys = len(self.names)
        self.n_determined = self.nvarys - len(self.undetermined)
        self.x = np.array([self.parameters[n].magnitude for n in self.names], dtype=float)
        to_display = np.array([p.scale * p.factor for p in free], dtype=float)
        self.jac = np.asarray(solution.jac, dtype=float) / to_display
        self.residual = np.asarray(solution.residual_weighted, dtype=float) / float(
            solution.residual_scale)
        self.channels = _channel_stats(solution.channels)
        # the extension channel's own degrees of freedom (all of nfree without torque)
        self.residual_rms = self.channels["extension"]["residual_rms"]
        self.goodness = dict(solution.goodness)
        self.ndata = int(solution.ndata)
        term = log_likelihood_term(solution.channels, float(solution.chi_square), self.ndata)
        self.aic = term + 2 * self.n_determined
        self.bic = term + math.log(self.ndata) * self.n_determined
        self.nfev, self.njev = int(solution.nfev), int(solution.njev)
        self.kernel_calls = int(solution.kernel_calls)
        self.kernel_failures = int(solution.kernel_failures)
        self.message = solution.message
        self.success = solution.success
        self.weighting = spec.data.weighting
        self.thermal = spec.thermal
        self.seconds = float(solution.seconds)
        self.cpu_seconds = float(solution.cpu_seconds)
        self.curve_cpu_seconds = (math.nan if solution.curve_cpu_seconds is None
                                  else float(solution.curve_cpu_seconds))
        self.best_fit = display.quantity(solution.best_fit, "extension")
        self.residuals = display.quantity(resid, "extension")
        self.warnings = [m for _, m in solution.warnings]
        self.notes = list(solution.notes)
        self.torque_best_fit = self.torque_residuals = None
        if spec.data.has_torque:
            self.torque_best_fit = display.quantity(solution.torque, "torque")
            self.torque_residuals = display.quantity(spec.data.torque - solution.torque,
                                                     "torque")
        self.model = solution.model
        self.interaction = solution.interaction
        self.fixed = self._fixed(solution, spec)
        si = solution.dna
        self.dna = dna.replace(**{p: display.quantity(getattr(si, p), "length")
                                  for p in spec.vary if p in DNA_FIELDS})

    @property
    def warning_records(self) -> list[tuple[str, str]]:
        """Every warning of the fit as ``(category name, message)``."""
        return list(self.solution.warnings)

    # the two tables are built on first use: a DataFrame costs a few percent of a fit
    @functools.cached_property
    def covariance(self) -> pd.DataFrame:
        """Covariance of the free parameters (display units, ``attrs["units"]``)."""
        cov = pd.DataFrame(self._cov, index=self.names, columns=self.names)
        cov.attrs["units"] = dict(self.units)
        return cov

    @functools.cached_property
    def correlation(self) -> pd.DataFrame:
        """Correlation matrix of the free parameters (NaN rows for undetermined ones)."""
        corr = pd.DataFrame(_correlation(self._cov, self._undetermined_mask),
                            index=self.names, columns=self.names)
        corr.attrs["units"] = {k: "" for k in self.names}
        return corr

    @staticmethod
    def _fixed(solution, spec):
        si = solution.dna
        fixed = {p: display.quantity(getattr(si, p), "length") for p in DNA_FIELDS
                 if p not in spec.vary}
        fixed["temperature"] = display.quantity(si.temperature, "temperature")
        for obj in (solution.model, solution.interaction):
            for k, q in obj.quantities().items():
                if k not in spec.vary:
                    fixed[k] = q
        for p in spec.params.values():
            if p.owner in ("offset", "calibration") and not p.vary:
                fixed[p.name] = p.quantity()
        return fixed

    # ---- text -------------------------------------------------------------------------
    def __repr__(self):
        vals = ", ".join(
            f"{k}={fmt_pm(self.parameters[k].magnitude, self.stderr[k].magnitude)} "
            f"{self.units[k]}" for k in self.names)
        return f"<FitResult {vals}; {self.headline()}>"

    def headline(self, digits=4):
        """The fit-quality figure: noise estimate (unit weights) or reduced chi-square."""
        if self.weighting == "unit":
            return f"noise estimate {self.residual_rms.magnitude:.{digits}g} nm"
        return f"reduced chi-square {self.reduced_chi_square:.{digits}g}"

    def report(self, min_correlation=0.1, max_correlations=6) -> str:
        """A fit report: statistics, parameter table with units, fixed values, correlations.

        Only the ``max_correlations`` largest correlations with ``|C| >=
        min_correlation`` are listed (lmfit's ``min_correl``); the full matrix
        is :attr:`correlation`.
        """
        from supercoil.dna.fitting.report import fit_report

        return fit_report(self, min_correlation, max_correlations)

    def profile(self, name, confidence_level=0.6827, max_steps=12, step=0.5):
        """Profile likelihood of one parameter (the others refitted at each step).

        Returns a :class:`~supercoil.dna.fitting.profile.ProfileLikelihood`
        (``lower_bound``, ``upper_bound``, ``interval(level)``, ``plot()``);
        pylake's ``profile_likelihood``. ``step`` is in standard errors; at
        most ``max_steps`` refits on each side (docs/theory/fitting.md#profile-likelihood).
        """
        from supercoil.dna.fitting.profile import profile_likelihood

        return profile_likelihood(self, name, confidence_level, max_steps, step)

    def conf_interval(self, names=None, sigmas=(1, 2), max_steps=12, step=0.5):
        """Profile-likelihood intervals (lmfit's ``conf_interval``): one row per parameter
        with ``best``, ``stderr``, ``lower_<s>sigma`` and ``upper_<s>sigma`` (display units).
        """
        from supercoil.dna.fitting.profile import conf_interval

        return conf_interval(self, names, sigmas, max_steps, step)

    def plot(self, fig=None, n_curve=300, path=None, dpi=120):
        """Data, fit and residuals per force (offset-corrected); returns the Figure.

        Like every matplotlib function that makes a figure, this draws and
        shows nothing by itself: in a notebook the returned Figure is
        displayed; in a script call ``matplotlib.pyplot.show()`` (an
        interactive backend) or save it, ``fit.plot(path="fit.png")`` or
        ``fit.plot().savefig("fit.png")``. On a non-interactive backend (Agg,
        the default without a display) ``show()`` shows nothing: save it.
        See :func:`~supercoil.dna.fitting.plot.plot_fit` for ``fig``, ``n_curve``,
        ``path`` and ``dpi``.
        """
        from supercoil.dna.fitting.plot import plot_fit

        return plot_fit(self, fig=fig, n_curve=n_curve, path=path, dpi=dpi)

    # ---- tables -------------------------------------------------------------------------
    def to_frame(self) -> pd.DataFrame:
        """One-row table (package convention): every free parameter and its stderr, fit stats.

        Columns ``<name>`` and ``<name>_stderr`` in the units of ``parameters``
        (``attrs["units"]``; the stderr is ``inf`` for an undetermined
        parameter), then ``reduced_chi_square``, ``chi_square``, ``aic``,
        ``bic`` (see the class docstring), ``residual_rms`` (nm), ``ndata``, ``nfree``, ``nfev``,
        ``weighting``, ``determined`` (False if any parameter is undetermined);
        with torque data also ``torque_residual_rms`` (pN nm),
        ``torque_chi_square``, ``torque_weighting``.
        """
        cols, units = {}, {}
        for name in self.names:
            cols[name] = [self.parameters[name].magnitude]
            cols[f"{name}_stderr"] = [self.stderr[name].magnitude]
            units[name] = units[f"{name}_stderr"] = self.units[name]
        for k, v, unit in (("reduced_chi_square", self.reduced_chi_square, ""),
                           ("chi_square", self.chi_square, ""),
                           ("aic", self.aic, ""), ("bic", self.bic, ""),
                           ("residual_rms", self.residual_rms.magnitude, "nm"),
                           ("ndata", self.ndata, ""), ("nfree", self.nfree, ""),
                           ("nfev", self.nfev, ""), ("weighting", self.weighting, ""),
                           ("determined", not self.undetermined, "")):
            cols[k] = [v]
            units[k] = unit
        if "torque" in self.channels:
            t = self.channels["torque"]
            cols["torque_residual_rms"] = [t["residual_rms"].m_as("pN*nm")]
            cols["torque_chi_square"] = [t["chi_square"]]
            cols["torque_weighting"] = [t["weighting"]]
            units.update(torque_residual_rms="pN*nm", torque_chi_square="",
                         torque_weighting="")
        prov = provenance(self.dna, vary=list(self.vary), fixed=dict(self.fixed),
                          thermal=self.thermal, model=self.model.name,
                          interaction=self.interaction.name)
        return make_table(cols, units, prov)

    def points_frame(self) -> pd.DataFrame:
        """Per-point table: data, offset-corrected turns, best fit, residual, phase flags."""
        d, c = self.spec.data, self.solution
        cols, units = {}, {}
        if d.has_molecule:
            cols["molecule"] = [d.labels[i] for i in d.mol_index]
            units["molecule"] = ""
        n_eff = d.turns - c.turns_offset[d.mol_index]
        for k, v, kind in (
            ("force", d.force, "force"),
            ("turns", d.turns, "turns"),
            ("turns_corrected", n_eff, "turns"),
            ("extension", d.extension, "extension"),
            ("best_fit", c.best_fit, "extension"),
            ("residual", d.extension - c.best_fit, "extension"),
            ("torque", c.torque, "torque"),
            *(() if d.torque is None else (
                ("torque_measured", d.torque, "torque"),
                ("torque_residual", d.torque - c.torque, "torque"))),
            ("plectoneme_length", c.plectoneme_length, "plectoneme_length"),
        ):
            cols[k] = display.to_display(v, kind)
            units[k] = display.unit(kind)
        cols["phase"], units["phase"] = c.phase.astype(int), ""
        cols["short_tail"], units["short_tail"] = c.short_tail, ""
        return make_table(cols, units, provenance(self.dna, vary=list(self.vary),
                                                  model=self.model.name))
