"""Issue 22 item 6: the result names lmfit and scipy users know, a dimensionless chi-square,
and a report that lists only the largest correlations."""

import numpy as np
import pytest
from fitting_helpers import NOISE, simulate

import supercoil as sc


def test_lmfit_and_scipy_names(result):
    r = result
    assert r.success is True and r.nfev > 0
    assert r.chisqr == r.chi_square and r.redchi == r.reduced_chi_square
    assert r.nvarys == len(r.names) == 4 and r.n_determined == 4
    # x: the best-fit values in display units, in the order of names
    assert r.x == pytest.approx([r.parameters[n].magnitude for n in r.names], rel=1e-15, abs=0)
    # jac: Jacobian of the normalised residuals in display units; its normal matrix is the
    # inverse covariance, and the residuals' squares sum to chisqr
    assert r.jac.shape == (r.ndata, r.nvarys)
    assert r.residual @ r.residual == pytest.approx(r.chisqr, rel=1e-12)
    cov = np.linalg.inv(r.jac.T @ r.jac)
    assert cov == pytest.approx(r.covariance.to_numpy(), rel=1e-6)
    # lmfit's definitions on the sum of squares (1 nm unit weights)
    ss = r.sum_squares.m_as("nm**2")
    n, k = r.ndata, r.n_determined
    assert r.aic == pytest.approx(n * np.log(ss / n) + 2 * k, rel=1e-12)
    assert r.bic == pytest.approx(n * np.log(ss / n) + np.log(n) * k, rel=1e-12)
    row = r.to_frame().iloc[0]
    assert row["aic"] == pytest.approx(r.aic) and row["bic"] == pytest.approx(r.bic)


def test_reduced_chi_square_is_dimensionless(result, true_dna, base):
    """It was the residual variance in nm^2 with unit weights."""
    assert result.reduced_chi_square == pytest.approx(1.0, rel=1e-12)
    assert result.residual_rms.m_as("nm") == pytest.approx(NOISE, rel=0.15)
    r = sc.fit_hat_curves(simulate(true_dna, seed=11, sigma_column=True), base,
                          vary=["twist_persistence", "radius"])
    assert r.redchi == pytest.approx(1.0, abs=0.2)
    assert r.redchi == pytest.approx(result.sum_squares.m_as("nm**2") / NOISE**2 / r.nfree,
                                     rel=1e-6)


def test_report_lists_the_largest_correlations_only(result):
    corr = result.correlation.to_numpy()
    iu = np.triu_indices(len(result.names), 1)
    big = np.sort(np.abs(corr[iu]))[::-1]
    big = big[big >= 0.1]
    assert len(big) >= 2
    text = result.report(max_correlations=1)
    block = text.split("[[Correlations]]")[1].split("[[")[0]
    lines = [ln for ln in block.splitlines()[1:] if ln.strip().startswith("C(")]
    assert len(lines) == 1
    assert abs(float(lines[0].split("=")[1])) == pytest.approx(big[0], abs=1e-4)
    assert f"the 1 largest of {len(big)}" in block
    assert "Akaike info crit" in text and "Bayesian info crit" in text
