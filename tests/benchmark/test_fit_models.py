"""The fit-cost benchmark of the physical models: its rows, ratios and fits."""

import numpy as np

from supercoil.benchmark.fit_models import PROBLEMS, UNITS, fit_model_cost
from supercoil.tables import make_table

SAME, OWN = "3 forces x 110 points", "3 forces x 110 points, each on data it made"


def test_rows_ratios_and_the_fits_behind_them():
    """Each problem gives a row per construction, the first its reference; the same-data
    problem's screened fit misfits the hard-core curves by far more than the noise, which
    is what the problem 'each on data it made' leaves out: there both fits reach the
    5 nm noise."""
    assert PROBLEMS[OWN][3] is None and PROBLEMS[OWN][4] == PROBLEMS[SAME][4]
    rows = fit_model_cost(samples=1, problems=[SAME, OWN])
    assert make_table(rows, UNITS).shape == (4, len(UNITS))
    assert rows["model"] == ["li-zhao/hard-core", "free-energy/screened"] * 2
    assert rows["points"] == [330] * 4
    time, ratio = np.array(rows["time"]), np.array(rows["ratio_to_li_zhao"])
    np.testing.assert_allclose(ratio, time / np.repeat(time[::2], 2), rtol=1e-12)
    rms = np.array(rows["residual_rms"])
    assert 4.5 < rms[0] < 5.5 and rms[1] > 100.0  # same curves: the screened model misfits
    assert np.all((4.5 < rms[2:]) & (rms[2:] < 5.5))  # each on its own curves: the noise
