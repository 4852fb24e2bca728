"""What the fit engine returns: :class:`FitSolution`, typed plain data (SI floats, arrays).

:func:`~supercoil.dna.fitting.fit.run_fit` builds it; it is picklable (a worker
process of :func:`~supercoil.fit_many` sends it back), and
:class:`~supercoil.dna.fitting.result.FitResult` turns it into quantities.
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["FitSolution"]


@dataclasses.dataclass(frozen=True, eq=False)
class FitSolution:
    """The result of one run of the fit engine, in SI units and scaled variables.

    Attributes
    ----------
    names : list of str
        The free parameters, in the order of every vector below.
    params : FitParameters
        All parameters with the estimates and standard errors set (SI).
    values, stderr, start : numpy.ndarray
        Estimates, one-sigma errors (``inf``: undetermined) and start values (SI).
    covariance : numpy.ndarray
        Covariance of ``values`` (SI).
    undetermined : numpy.ndarray of bool
        The free parameters the data do not determine.
    chi_square, reduced_chi_square : float
        The raw weighted sum of squares (1 m unit weights without sigmas) and
        it over ``nfree``.
    chisqr, redchi : float
        The dimensionless chi-square (:attr:`FitResult.chisqr`) and it over ``nfree``.
    ndata, nfree : int
        Residuals (points of every channel) and degrees of freedom.
    jac : numpy.ndarray
        Jacobian of the normalised residuals in the scaled variables.
    residual_weighted : numpy.ndarray
        The weighted residuals; divided by ``residual_scale`` they are normalised.
    residual_scale : float
        The noise estimate that normalises the residuals (1 with sigmas).
    nfev, njev, kernel_calls, kernel_failures : int
        Model and Jacobian evaluations, kernel calls (both), kernel failures.
    status : int
        scipy's ``least_squares`` status (``> 0``: converged); ``message`` its text.
    dna : DNASI
        The molecule with the fitted global fields (SI).
    model, interaction
        The model and interaction instances with the fitted parameters.
    turns_offset, extension_offset : numpy.ndarray
        Per molecule: turns offset (turn) and extension offset (m).
    extension_offset_points : numpy.ndarray
        The extension offset of every data point (m; per curve with per-force offsets).
    states : dict or None
        With per-force parameters: force (N) -> ``(dna, model, interaction)`` at that force.
    best_fit, torque : numpy.ndarray
        The model extension (m, offsets included) and torque (N m) at the data points.
    phase, short_tail, plectoneme_length : numpy.ndarray
        Per point: the model's phase code, the short-tail flag, the plectoneme length (m).
    calibration : dict of str -> float
        The calibration scales (``force_scale``, ``torque_scale``).
    goodness : dict
        The goodness-of-fit test and its ``p_value``.
    warnings : list of (str, str)
        ``(category name, message)`` records, issued by the caller.
    channels : dict of str -> dict
        Per channel plain statistics (``n``, ``chi_square``, ``dof``,
        ``weighting``, ``rms``, ``noise``; SI).
    notes : list of str
        What the preparation and the start values decided for the user.
    seconds, cpu_seconds : float
        Wall-clock and CPU time of the run (``time.perf_counter``, ``time.process_time``).
    curve_cpu_seconds : float or None
        CPU time of one evaluation of the model at the data points with the
        best-fit parameters (``time.process_time``), when the caller asked for it.
    """

    names: list
    params: object
    values: np.ndarray
    stderr: np.ndarray
    start: np.ndarray
    covariance: np.ndarray
    undetermined: np.ndarray
    chi_square: float
    reduced_chi_square: float
    chisqr: float
    redchi: float
    ndata: int
    nfree: int
    jac: np.ndarray
    residual_weighted: np.ndarray
    residual_scale: float
    nfev: int
    njev: int
    kernel_calls: int
    kernel_failures: int
    status: int
    message: str
    dna: object
    model: object
    interaction: object
    turns_offset: np.ndarray
    extension_offset: np.ndarray
    extension_offset_points: np.ndarray
    states: dict | None
    best_fit: np.ndarray
    torque: np.ndarray
    phase: np.ndarray
    short_tail: np.ndarray
    plectoneme_length: np.ndarray
    calibration: dict
    goodness: dict
    warnings: list
    channels: dict
    notes: list
    seconds: float
    cpu_seconds: float
    curve_cpu_seconds: float | None = None

    @property
    def success(self) -> bool:
        """The optimiser converged (scipy's ``status > 0``)."""
        return self.status > 0
