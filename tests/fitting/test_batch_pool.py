"""fit_many on a process pool: one molecule per submit or chunks, identical to serial."""

import os
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import pandas as pd
import pytest

import supercoil as sc
from supercoil.dna.fitting import batch, simulate_rotation_curves

VARY = ["twist_persistence", "radius"]


def _fit(many, base, executor=None):
    seen = []
    table = sc.fit_many(many, base, vary=VARY, executor=executor,
                        progress=lambda done, total, mol: seen.append((done, total, mol)))
    return table, seen


def test_pool_one_per_submit_and_chunked_equal_serial_exactly(many, base, monkeypatch):
    """Parameters, stderr, row order, labels and the failed molecule (m3) identical."""
    serial, _ = _fit(many, base)
    with ProcessPoolExecutor(max_workers=2) as pool:
        assert batch._chunk_sizes(4, pool) == [1, 1, 1, 1]  # few molecules: one per submit
        single, seen_single = _fit(many, base, pool)
        monkeypatch.setattr(batch, "POOL_CHUNK", 3)
        monkeypatch.setattr(batch, "POOL_TAIL", 1)
        assert batch._chunk_sizes(4, pool) == [3, 1]
        chunked, seen_chunked = _fit(many, base, pool)
    for table in (single, chunked):
        pd.testing.assert_frame_equal(serial, table, check_exact=True)
        assert table.attrs == serial.attrs
    assert list(serial["molecule"]) == ["m1", "m2", "m3", "m4"]
    assert list(serial["success"]) == [True, True, False, True]
    assert "no plectoneme equilibrium" in serial.loc[2, "error"]
    for seen in (seen_single, seen_chunked):  # progress per molecule, chunks or not
        assert [d for d, _, _ in seen] == [1, 2, 3, 4] and {t for _, t, _ in seen} == {4}
        assert sorted(m for _, _, m in seen) == ["m1", "m2", "m3", "m4"]


def test_chunk_sizes_cover_every_molecule_with_a_tail_of_single_molecules():
    with ProcessPoolExecutor(max_workers=1) as pool:
        for n in (0, 1, 15, 16, 63, 64, 200, 2001):
            sizes = batch._chunk_sizes(n, pool)
            assert sum(sizes) == n and all(1 <= k <= batch.POOL_CHUNK for k in sizes)
            assert sizes == sorted(sizes, reverse=True)  # the large chunks first
            assert sizes[-batch.POOL_TAIL:] == [1] * min(n, batch.POOL_TAIL)
        assert batch._chunk_sizes(200, pool)[0] == batch.POOL_CHUNK
    with ThreadPoolExecutor(max_workers=1) as threads:  # other executors: one per submit
        assert batch._chunk_sizes(200, threads) == [1] * 200


def _task(frame, base):
    from supercoil.dna.fitting.fit import prepare

    spec = prepare(frame, base)
    return batch.MoleculeTask("m", spec.data, spec, batch._layout(spec)), spec


def test_only_a_large_fit_limits_blas_threads_in_a_worker(many, base, true_dna, monkeypatch):
    """Limiting BLAS starts the BLAS threads of a fresh worker (~0.1 s of CPU spinning):
    only fits large enough to run BLAS threaded are limited, and only in a worker."""
    from threadpoolctl import threadpool_info, threadpool_limits

    u = sc.ureg
    one = many[many["molecule"] == "m1"].drop(columns="molecule").reset_index(drop=True)
    one.attrs = dict(many.attrs)
    small, spec = _task(one, base)
    assert spec.data.n * len(spec.params.free) < batch.BLAS_LIMIT_FROM
    large, spec = _task(simulate_rotation_curves(true_dna, [0.3, 0.5, 0.7] * u.pN,
                                                 points_per_force=700, noise=5 * u.nm,
                                                 seed=3), base)
    assert spec.data.n * len(spec.params.free) >= batch.BLAS_LIMIT_FROM
    seen = []
    real = batch.run_fit

    def spy(s):
        seen.append(max(i["num_threads"] for i in threadpool_info()))
        return real(s)

    monkeypatch.setattr(batch, "run_fit", spy)
    with threadpool_limits(limits=2):
        for task, pid in ((small, -1), (large, -1), (large, os.getpid())):  # -1: "a worker"
            assert batch._fit_worker(task, parent_pid=pid)[0]["success"]
        after = max(i["num_threads"] for i in threadpool_info())
    assert seen == [2, 1, 2] and after == 2


def _threads_around_fit(task, parent_pid):
    """Native threads of this (worker) process before and after one fit."""
    before = len(os.listdir("/proc/self/task"))
    row, _ = batch._fit_worker(task, parent_pid)
    return before, len(os.listdir("/proc/self/task")), row["success"]


@pytest.mark.skipif(not os.path.isdir("/proc/self/task"), reason="counts threads in /proc")
def test_small_fit_starts_no_blas_thread_in_a_fresh_worker(many, base):
    """The cause of a missing pool speed-up: a worker's first BLAS limit started the
    BLAS threads (which then spin); a small fit now starts none."""
    one = many[many["molecule"] == "m1"].drop(columns="molecule").reset_index(drop=True)
    one.attrs = dict(many.attrs)
    task, _ = _task(one, base)
    with ProcessPoolExecutor(max_workers=1) as pool:
        before, after, ok = pool.submit(_threads_around_fit, task, os.getpid()).result()
    assert ok and after == before
