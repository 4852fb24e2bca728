"""The noise of each channel of a joint extension-torque fit, its weights and statistics.

docs/theory/fitting.md#joint-torque-fit.

Per-channel noise estimates (the weights of a channel without sigmas), the
re-solve until they settle, per-channel statistics and the chi-square that the
goodness-of-fit test may use (channels with stated sigmas only).
"""

from __future__ import annotations

import numpy as np

__all__ = ["channel_noise", "channels_info", "joint_noise", "tested_chi2"]


def channel_noise(prob, u, nparams):
    """Residual RMS of each channel (SI) with the degrees of freedom shared by point count.

    ``sqrt(sum r_c^2 / (n_c - p n_c / n))`` for channel c with n_c of the n
    points and p free parameters (docs/theory/fitting.md#joint-torque-fit).
    """
    d = prob.predicted(u) - prob.observed
    n = len(d)
    out = []
    for part in (d[: prob.n_ext], d[prob.n_ext:]):
        dof = len(part) * (1.0 - nparams / n)
        out.append(float(np.sqrt(part @ part / dof)) if len(part) else float("nan"))
    return out


def joint_noise(spec, prob, res, solve):
    """Re-solve with the noise estimates of the channels without sigmas until they settle.

    Extension-only fits need none of this (the covariance is rescaled by the
    noise); with torque each channel without sigmas gets its own weight, its
    residual RMS (at most 6 re-solves, to 0.1 %).
    """
    data = spec.data
    est_z, est_t = data.weighting == "unit", data.torque_weighting == "unit"
    noise = {}
    if not data.has_torque or not (est_z or est_t):
        return res, noise
    nfev = res.nfev
    for _ in range(6):
        sz, st = channel_noise(prob, res.x, len(res.x))
        old = dict(noise)
        if est_z:
            noise["extension"] = max(sz, 1e-15)
            prob.set_extension_sigma(noise["extension"])
        if est_t:
            noise["torque"] = max(st, 1e-27)
            prob.set_torque_sigma(noise["torque"])
        res = solve(spec, prob, res.x)
        nfev += res.nfev
        if old and all(abs(noise[k] / old[k] - 1) < 1e-3 for k in noise):
            break
    res.nfev = nfev  # all solves
    return res, noise


def channels_info(spec, prob, u, noise):
    """Per-channel statistics: points, chi-square, residual RMS (SI), weighting, noise."""
    r = prob.residual(u)
    d = prob.predicted(u) - prob.observed
    n, p = len(r), len(u)
    info = {}
    names = ("extension", "torque") if spec.data.has_torque else ("extension",)
    for c, name in enumerate(names):
        sl = slice(c * prob.n_ext, (c + 1) * prob.n_ext)
        nc = prob.n_ext
        weighting = spec.data.weighting if c == 0 else spec.data.torque_weighting
        info[name] = {"n": nc, "chi_square": float(r[sl] @ r[sl]),
                      "dof": nc * (1.0 - p / n),
                      "rms": float(np.sqrt(d[sl] @ d[sl] / (nc * (1.0 - p / n)))),
                      "weighting": weighting, "noise": noise.get(name)}
    return info


def tested_chi2(channels, nfree):
    """Chi-square and degrees of freedom of the channels with stated sigmas (the test's)."""
    given = [c for c in channels.values() if c["weighting"] != "unit"]
    if len(given) == len(channels):
        return sum(c["chi_square"] for c in given), nfree
    if not given:
        return sum(c["chi_square"] for c in channels.values()), nfree
    return sum(c["chi_square"] for c in given), sum(c["dof"] for c in given)
