"""fit_many on a real dask.distributed LocalCluster (two worker processes).

dask[distributed] is installed by the test extra: without it this test fails
(an import error), it is never skipped.
"""

import dask
import numpy as np
import pandas as pd
from distributed import Client, LocalCluster
from fitting_helpers import FORCES

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves


def _frame(true_dna):
    u = sc.ureg
    return simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=40,
                                    molecules=4, turns_offset=[0.2, -0.3, 0.5, 0.0],
                                    extension_offset=[10, 0, -5, 20] * u.nm, seed=8)


def test_fit_many_on_a_local_cluster_equals_serial(true_dna, base, monkeypatch):
    from supercoil.dna.fitting import batch

    df = _frame(true_dna)
    serial = sc.fit_many(df, base, progress=False)
    seen = []
    # the worker processes are forked (dask's "fork" method) rather than spawned: separate
    # processes all the same (checked below), without paying a fresh interpreter's imports
    # of supercoil, dask and scipy in each; the tables still travel pickled
    with (dask.config.set({"distributed.worker.multiprocessing-method": "fork"}),
          LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                       dashboard_address=None) as cluster,
          Client(cluster) as client):
        on_client = sc.fit_many(df, base, executor=client,
                                progress=lambda d, t, m: seen.append((d, t, m)))
        on_executor = sc.fit_many(df, base, executor=client.get_executor(), progress=False)
        # large tables go to dask in chunks of molecules: chunks of 3 and 1 here
        monkeypatch.setattr(batch, "_chunk_size", lambda n: 3)
        chunked = sc.fit_many(df, base, executor=client, progress=False)
        # the fits ran in the worker processes, not in this one
        pids = set(client.run(lambda: __import__("os").getpid()).values())
    assert len(pids) == 2 and __import__("os").getpid() not in pids
    cols = [c for c in serial.columns if c != "warnings"]
    for par in (on_client, on_executor, chunked):
        pd.testing.assert_frame_equal(serial[cols], par[cols], rtol=1e-9)
        assert par.attrs["units"] == serial.attrs["units"]
    assert serial["success"].all()
    assert sorted(d for d, _, _ in seen) == [1, 2, 3, 4]
    assert {m for _, _, m in seen} == {"m1", "m2", "m3", "m4"}
