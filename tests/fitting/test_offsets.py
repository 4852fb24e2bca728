"""Issue 22 item 3: a molecule is one bead: one extension offset for all its forces by
default; one per force only on request."""

import numpy as np
import pytest
from fitting_helpers import FORCES, TRUE_Z0, simulate

import supercoil as sc


def test_default_is_one_extension_offset_per_molecule(result, many, base):
    assert [n for n in result.names if n.startswith("extension_offset")] == ["extension_offset"]
    assert result.parameters["extension_offset"].m == pytest.approx(TRUE_Z0, abs=3)
    r = sc.fit_parameters(many, base)
    z = [n for n in r if n.startswith("extension_offset")]
    assert z == [f"extension_offset[m{i}]" for i in range(1, 5)]
    assert all(r[n].shared == "per-molecule" for n in z)


def test_per_force_offsets_on_request(true_dna, base, result):
    df = simulate(true_dna, seed=11)
    # the curve at the middle force is referenced 25 nm higher
    df.loc[df["force"] == FORCES[1], "extension"] += 0.025  # um
    r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"],
                          fit_extension_offset="per-force")
    names = [n for n in r.names if n.startswith("extension_offset")]
    assert names == [f"extension_offset[{f:g} pN]" for f in FORCES]
    z = [r.parameters[n].m_as("nm") for n in names]
    assert z[0] == pytest.approx(TRUE_Z0, abs=3) and z[2] == pytest.approx(TRUE_Z0, abs=3)
    assert z[1] - z[0] == pytest.approx(25, abs=3)
    assert r.parameters["twist_persistence"].m_as("nm") == pytest.approx(95, abs=3)
    # the exact offset columns: the covariance from the Jacobian, the curve's own error
    assert r.jac.shape == (len(df), len(r.names))
    for n in names:
        assert 0 < r.stderr[n].m_as("nm") < 3
    # the points table and the plot use the per-curve offsets
    fig = r.plot()
    import matplotlib.pyplot as plt

    plt.close(fig)
    resid = r.residuals.m_as("nm")
    assert np.std(resid) == pytest.approx(5, rel=0.2)
    # "per-molecule" is the default spelled out
    r1 = sc.fit_hat_curves(simulate(true_dna, seed=11), base,
                           vary=["twist_persistence", "radius"],
                           fit_extension_offset="per-molecule")
    assert r1.parameters["extension_offset"].m == pytest.approx(
        result.parameters["extension_offset"].m, rel=1e-12)
    with pytest.raises(TypeError, match=r"fit_extension_offset must be .* 'per-force'"):
        sc.fit_hat_curves(df, base, fit_extension_offset="per-curve")
