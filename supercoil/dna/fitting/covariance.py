"""Covariance of the fitted parameters from the thin SVD of the weighted Jacobian.

docs/theory/fitting.md#covariance. ``cov = (J^T J)^-1 = V S^-2 V^T`` from
the thin SVD ``J = U S V^T`` (``U`` is n x m, never the unused n x n matrix of
the full SVD), with the parameters the data do not determine marked.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["JAC_RTOL", "covariance"]

#: Relative accuracy of the Jacobian's columns: the forward-difference step (the
#: truncation error of a forward difference is O(h) relative; h = 1e-6 in the
#: scaled variables, which are of order one).
JAC_RTOL = 1e-6


def covariance(J, names=None):
    """``(J^T J)^-1`` by thin SVD, with the parameters the data do not determine.

    Rank threshold: a singular value ``s_k < s_max * JAC_RTOL * sqrt(n_par)``
    counts as zero. Justification: each column of the finite-difference
    Jacobian has a relative error of about ``JAC_RTOL``, so the error matrix
    ``E`` has ``||E||_2 <= ||E||_F <= JAC_RTOL * ||J||_F <= JAC_RTOL *
    sqrt(n_par) * s_max``, and by Weyl's inequality a singular value below that
    cannot be told from zero. (numpy's ``matrix_rank`` default, ``eps * max(shape)
    * s_max``, assumes entries exact to rounding; ours are differences.)

    A parameter is *undetermined* when its unit vector has a component larger
    than the same tolerance in the numerical null space: moving along that
    null direction leaves the residuals unchanged, so its variance is infinite.
    Its standard error is ``inf`` and its covariance row and column are NaN.
    The covariance of the other parameters is the pseudo-inverse restricted to
    them, which equals their covariance with the undetermined ones profiled out.

    Parameters
    ----------
    J : ndarray, shape (n, m), n >= m
        Weighted Jacobian in the scaled variables.
    names : sequence of str, optional
        Parameter names for the message.

    Returns
    -------
    cov : ndarray (m, m)
        Covariance in the scaled variables (NaN rows/columns for undetermined ones).
    undetermined : ndarray of bool (m,)
    note : str or None
        Warning text naming the undetermined parameters (None at full rank).
    """
    J = np.asarray(J, dtype=float)
    n_par = J.shape[1]
    names = list(names) if names is not None else [f"p{j}" for j in range(n_par)]
    _, s, vt = np.linalg.svd(J, full_matrices=False)
    s_full = np.zeros(n_par)  # n < m cannot happen in a fit (checked), kept for safety
    s_full[: s.size] = s
    if vt.shape[0] < n_par:
        vt = np.linalg.svd(J, full_matrices=True)[2]
    s_max = s_full[0] if s_full.size else 0.0
    rtol = JAC_RTOL * math.sqrt(n_par)
    keep = s_full > s_max * rtol if s_max > 0 else np.zeros(n_par, dtype=bool)
    null = vt[~keep]
    undetermined = (np.sqrt(np.sum(null**2, axis=0)) > rtol if null.size
                    else np.zeros(n_par, dtype=bool))
    vt_k = vt[keep]
    cov = (vt_k.T / s_full[keep] ** 2) @ vt_k
    note = None
    if undetermined.any():
        cov[undetermined, :] = np.nan
        cov[:, undetermined] = np.nan
        bad = [n for n, u in zip(names, undetermined, strict=True) if u]
        one = len(bad) == 1
        note = (
            f"the Jacobian is singular (rank {int(keep.sum())} of {n_par}, relative "
            f"singular-value threshold {rtol:.2g}): the data do not determine "
            f"{', '.join(bad)}; {'its' if one else 'their'} standard error"
            f"{'' if one else 's'} {'is' if one else 'are'} inf"
        )
    return cov, undetermined, note
