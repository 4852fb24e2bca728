"""fit_many: per-molecule fits, failures per molecule, executors."""

from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest
from fitting_helpers import FORCES

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.exceptions import (
    FitError,
    FitWarning,
)


def _flat_molecule(base, forces, points, seed):
    """A nicked molecule: the extension does not change with the turns."""
    u = sc.ureg
    flat = simulate_rotation_curves(base, np.array(forces) * u.pN, turns=np.zeros(points),
                                    noise=5 * u.nm, seed=seed)
    return flat["extension"].to_numpy()


def test_fit_many_marks_a_flat_molecule_as_not_determined(true_dna, base):
    """A flat curve in fit_many had success True and stderr ~1e-11."""
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=40,
                                  noise=5 * u.nm, molecules=2, seed=1)
    flat = (df["molecule"] == "m2").to_numpy()
    df.loc[flat, "extension"] = _flat_molecule(true_dna, FORCES, 40, seed=3)
    with pytest.warns(FitWarning, match="molecule m2: .*do not determine radius"), \
            pytest.warns(FitWarning, match="molecule m2: .* plausible"):
        table = sc.fit_many(df, base, vary=["twist_persistence", "radius"])
    assert list(table["success"]) == [True, True]
    assert list(table["determined"]) == [True, False]
    assert np.isfinite(table.loc[0, "radius_stderr"]) and table.loc[0, "radius_stderr"] > 0
    assert not np.isfinite(table.loc[1, "radius_stderr"])
    assert "do not determine radius" in table.loc[1, "warnings"]


def test_fit_many_reports_the_points_of_a_molecule_rejected_in_preparation(true_dna, base):
    """Audit S3: 3 points for 4 free parameters was reported with ndata = 0."""
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=30,
                                  molecules=["a", "b"], seed=2)
    keep = (df["molecule"] == "a").to_numpy().copy()
    keep[np.flatnonzero(df["molecule"] == "b")[:3]] = True
    small = df.loc[keep].reset_index(drop=True)
    small.attrs = dict(df.attrs)
    table = sc.fit_many(small, base, vary=["twist_persistence", "radius"])
    assert list(table["success"]) == [True, False]
    assert "3 data points cannot determine 4 free parameters" in table.loc[1, "error"]
    assert list(table["ndata"]) == [90, 3]
    assert not table.loc[1, "determined"]


def _compare(a, b):
    cols = [c for c in a.columns if c not in ("warnings",)]
    pd.testing.assert_frame_equal(a[cols], b[cols], rtol=1e-9)


def test_fit_many_reports_failures_per_molecule(many, base):
    seen = []
    table = sc.fit_many(many, base, vary=["twist_persistence", "radius"],
                        progress=lambda done, total, mol: seen.append((done, total, mol)))
    assert list(table["molecule"]) == ["m1", "m2", "m3", "m4"]
    assert list(table["success"]) == [True, True, False, True]
    assert "no plectoneme equilibrium" in table.loc[2, "error"]
    assert np.isnan(table.loc[2, "twist_persistence"])
    assert (table.loc[[0, 1, 3], "error"] == "").all()
    assert [s[0] for s in seen] == [1, 2, 3, 4] and {s[1] for s in seen} == {4}
    assert {s[2] for s in seen} == {"m1", "m2", "m3", "m4"}
    assert table.attrs["units"]["radius_stderr"] == "nm"
    assert table.attrs["units"]["turns_offset"] == "turn"
    # each row equals the single-molecule fit
    for i, lab in ((0, "m1"), (3, "m4")):
        sub = many[many["molecule"] == lab].drop(columns="molecule").reset_index(drop=True)
        sub.attrs = dict(many.attrs)
        r = sc.fit_hat_curves(sub, base, vary=["twist_persistence", "radius"])
        for name in r.parameters:
            assert table.loc[i, name] == pytest.approx(r.parameters[name].m, rel=1e-9)
            assert table.loc[i, f"{name}_stderr"] == pytest.approx(r.stderr[name].m, rel=1e-9)
        # the fit statistics mean what FitResult's do: redchi dimensionless (1 with unit
        # weights), the noise estimate the extension residual RMS in nm (was nm^2 variance)
        assert table.loc[i, "reduced_chi_square"] == pytest.approx(r.redchi, rel=1e-9)
        assert table.loc[i, "residual_rms"] == pytest.approx(r.residual_rms.m_as("nm"),
                                                             rel=1e-9)
        assert 4 < table.loc[i, "residual_rms"] < 6  # simulated with 5 nm noise
        assert abs(table.loc[i, "twist_persistence"] - 95) < 4 * table.loc[
            i, "twist_persistence_stderr"]
    assert abs(table.loc[1, "turns_offset"] + 0.3) < 4 * table.loc[1, "turns_offset_stderr"]


@pytest.mark.parametrize("pool", [ThreadPoolExecutor, ProcessPoolExecutor])
def test_fit_many_in_parallel_equals_serial(many, base, pool):
    serial = sc.fit_many(many, base, vary=["twist_persistence", "radius"])
    seen = []
    with pool(max_workers=2) as ex:
        par = sc.fit_many(many, base, vary=["twist_persistence", "radius"], executor=ex,
                          progress=lambda d, t, m: seen.append(d))
    _compare(serial, par)
    assert sorted(seen) == [1, 2, 3, 4]


def test_fit_many_rejects_common_problems_up_front(many, base):
    with pytest.raises(FitError, match="cannot vary"):
        sc.fit_many(many, base, vary=["pitch"])
    with pytest.raises(FitError, match="each molecule is fitted alone"):
        sc.fit_many(many, base, fixed={"turns_offset[m1]": 0})


class _LazyFuture:
    def __init__(self, fn, args):
        self.fn, self.args = fn, args

    def result(self):
        return self.fn(*self.args)


class _NonStandardExecutor:
    """Like a dask Client: submit() returns futures that are not concurrent.futures.Future."""

    def submit(self, fn, *args):
        return _LazyFuture(fn, args)


def test_fit_many_with_a_client_like_executor(many, base):
    serial = sc.fit_many(many, base, vary=["twist_persistence", "radius"])
    other = sc.fit_many(many, base, vary=["twist_persistence", "radius"],
                        executor=_NonStandardExecutor())
    _compare(serial, other)


def test_fit_many_splits_a_per_point_sigma_by_molecule(many, base):
    sigma = np.where(many["molecule"] == "m2", 5.5, 5.0) * sc.ureg.nm
    ok = many[many["molecule"].isin(["m1", "m2"])].reset_index(drop=True)
    ok.attrs = dict(many.attrs)
    table = sc.fit_many(ok, base, sigma=sigma[: len(ok)])
    for i, lab in enumerate(["m1", "m2"]):
        sub = ok[ok["molecule"] == lab].drop(columns="molecule").reset_index(drop=True)
        sub.attrs = dict(ok.attrs)
        r = sc.fit_hat_curves(sub, base, sigma=(5.5 if lab == "m2" else 5.0) * sc.ureg.nm)
        assert table.loc[i, "radius_stderr"] == pytest.approx(r.stderr["radius"].m, rel=1e-9)
    assert table.attrs["provenance"]["weighting"] == "sigma argument"


def test_fit_many_checks_and_splits_the_table_once(many, base, monkeypatch):
    """Parent cost per molecule constant: one table check for all molecules, not one each."""
    from supercoil.dna.fitting import data as fit_data

    calls = []
    real = fit_data.check_tweezers_frame

    def spy(df, **kw):
        calls.append(len(df))
        return real(df, **kw)

    monkeypatch.setattr(fit_data, "check_tweezers_frame", spy)
    submitted = []

    class Recording(_NonStandardExecutor):
        def submit(self, fn, *args):
            submitted.append(args[0].data.n)  # each spec holds its own molecule's points only
            return super().submit(fn, *args)

    sc.fit_many(many, base, executor=Recording())
    assert calls == [len(many)]
    assert submitted == [int((many["molecule"] == m).sum()) for m in ("m1", "m2", "m3", "m4")]


def test_each_task_carries_its_molecule_only_not_the_table():
    """A task's pickled size does not grow with the number of molecules (the
    template once held the whole table, 26 MB per task at 2,000 molecules)."""
    from supercoil.benchmark.fit_many import client_cost

    small = client_cost(n_molecules=5, points_per_force=30, repeat=1)
    large = client_cost(n_molecules=60, points_per_force=30, repeat=1)
    assert small.attrs["units"]["client_time_per_molecule"] == "ms"
    kb_small = small["pickled_per_task"].iloc[0]
    kb_large = large["pickled_per_task"].iloc[0]
    assert kb_large == pytest.approx(kb_small, rel=0.02)
    # 90 points x 5 float arrays = 3.6 kB of data; the settings add a few kB at most
    assert 3.6 < kb_small < 12
