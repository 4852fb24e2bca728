"""The result object: tables, report text and figure."""


import numpy as np
import pytest
from fitting_helpers import FORCES, simulate

import supercoil as sc


def test_result_tables_report_and_plot(result, tmp_path):
    import matplotlib.figure

    names = list(result.parameters)
    cov, corr = result.covariance, result.correlation
    assert list(cov.index) == names and list(cov.columns) == names
    np.testing.assert_allclose(cov.to_numpy(), cov.to_numpy().T, rtol=1e-12, atol=0)
    np.testing.assert_allclose(np.diag(cov), [result.stderr[k].m ** 2 for k in names], rtol=1e-10)
    np.testing.assert_allclose(np.diag(corr), 1.0)
    assert np.all(np.abs(corr.to_numpy()) <= 1 + 1e-12)
    assert cov.attrs["units"]["radius"] == "nm" and cov.attrs["units"]["turns_offset"] == "turn"

    text = result.report()
    for token in ("noise estimate", "twist_persistence", "radius", "turns_offset",
                  "extension_offset", "nm", "turn", "bending_persistence", "[[Fixed]]",
                  "unit weights; standard errors scaled by the noise estimate",
                  "runs test (Wald-Wolfowitz)"):
        assert token in text, token
    assert "±" in repr(result)

    frame = result.to_frame()
    assert len(frame) == 1
    assert frame.attrs["units"]["twist_persistence"] == "nm"
    assert frame.attrs["units"]["twist_persistence_stderr"] == "nm"
    assert frame["radius"].iloc[0] == pytest.approx(result.parameters["radius"].m)
    back = sc.read_csv(sc.write_csv(frame, tmp_path / "p.csv"))
    assert back["radius"].iloc[0] == pytest.approx(result.parameters["radius"].m, rel=1e-10)

    pts = result.points_frame()
    assert len(pts) == result.ndata
    np.testing.assert_allclose(pts["residual"], result.residuals.m_as("nm"))
    np.testing.assert_allclose(pts["best_fit"] + pts["residual"], pts["extension"], rtol=1e-12)

    # in a plain script plot() showed and saved nothing: path= saves (its folder made)
    assert matplotlib.get_backend().lower() == "agg"  # as a script without a display
    path = tmp_path / "new folder" / "fit.png"
    fig = result.plot(path=path, dpi=40)
    assert isinstance(fig, matplotlib.figure.Figure)
    assert len(fig.axes) == 2 * len(FORCES)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    import matplotlib.image
    import matplotlib.pyplot as plt

    width, height = fig.get_size_inches()
    assert matplotlib.image.imread(path).shape[:2] == (round(height * 40), round(width * 40))

    plt.close(fig)


def test_unit_weights_show_the_noise_estimate_not_a_chi_square(result, true_dna, base):
    """Audit P3: with unit weights the headline is the residual RMS in nm."""
    import matplotlib.pyplot as plt

    noise = result.residual_rms.m_as("nm")
    fig = result.plot()
    title = fig._suptitle.get_text()
    plt.close(fig)
    assert f"noise estimate (residual RMS) {noise:.3g} nm" in title
    assert "chi-square" not in title
    text = result.report()
    stats = text.split("[[Fit statistics]]")[1].split("[[Parameters]]")[0]
    first = next(line for line in stats.splitlines() if "chi" in line or "noise" in line)
    # the residual RMS in the data's unit (um here), no reduced chi-square in nm^2
    assert first.strip().startswith(f"noise estimate     = {noise / 1000:.4g} um ({noise:.4g} nm)")
    assert "reduced chi-square" not in stats and "sum of squares" in stats
    assert "chi-square" not in repr(result)
    # with per-point sigma the reduced chi-square is a goodness of fit and stays in the title
    r = sc.fit_hat_curves(simulate(true_dna, seed=11, sigma_column=True), base,
                          vary=["twist_persistence", "radius"])
    fig = r.plot()
    title = fig._suptitle.get_text()
    plt.close(fig)
    assert f"reduced chi-square {r.reduced_chi_square:.3g}" in title
