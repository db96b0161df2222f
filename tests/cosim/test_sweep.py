"""Sweeps and regression suites on dask.distributed: a local cluster gives exactly the serial master's results."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("dask.distributed", reason="the dist extra (dask[distributed]) is not installed")

from dask.distributed import Client  # noqa: E402

from rollcontact_cosim.master import run_cosimulation  # noqa: E402
from rollcontact_cosim.sweep import Case, local_cluster, run_regression, run_sweep  # noqa: E402

STOP = 0.1  # s: a short piece of the scene is enough to compare


@pytest.fixture(scope="module")
def client():
    with local_cluster(2) as cluster, Client(cluster) as c:
        yield c


def test_a_sweep_on_worker_processes_equals_the_serial_runs(client):
    cases = [Case("carter_sanity", stop_time=STOP, contact={"friction_coefficient": mu}, keep_values=True)
             for mu in (0.25, 0.3)]
    results = run_sweep(cases, client=client)
    assert [r.case for r in results] == cases, "results come back in the order of the cases"
    for res in results:
        serial = run_cosimulation("carter_sanity", stop_time=STOP, contact=dict(res.case.contact))
        assert res.success, res.message
        assert np.array_equal(res.values, serial.values), \
            f"{res.case.contact}: a worker's run must equal the serial run bit for bit"
        assert res.summary["steps"] == serial.steps, "the summary counts the same steps"
    creeps = [r.summary["creep_at_peak"] for r in results]
    assert creeps[0] > creeps[1] > 0.0, f"the same traction needs more creep at lower friction, got {creeps}"


def test_a_failing_case_is_reported_and_does_not_stop_the_sweep(client):
    results = run_sweep([Case("carter_sanity", stop_time=STOP, contact={"friction_coefficient": -1.0}),
                         Case("carter_sanity", stop_time=STOP)], client=client)
    assert not results[0].success and "friction_coefficient" in results[0].message, results[0].message
    assert results[1].success, results[1].message


def test_the_regression_suite_runs_on_the_cluster(client):
    for scene, master, problems in run_regression(["carter_sanity"], ["fmpy"], client=client):
        assert problems == [], f"{scene} with {master}: {problems}"
