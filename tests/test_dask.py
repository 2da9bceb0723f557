"""Monte Carlo on a real Dask cluster (two worker processes on loopback): same results as serial.

Skipped, with the reason, when the ``setsmooth[dask]`` extra is not installed; the CI installs it.
"""

from __future__ import annotations

import functools
import os
import pickle
import time
from pathlib import Path

import numpy as np
import pytest

distributed = pytest.importorskip("distributed", reason="the setsmooth[dask] extra is not installed")

import setsmooth as ss  # noqa: E402
from setsmooth.runs.montecarlo import run  # noqa: E402


def draw(rng: np.random.Generator) -> np.ndarray:
    return rng.standard_normal(3)


def filter_trial(rng: np.random.Generator, T: int) -> dict:
    """Ships a system with an input sequence and a queried CZ noise out, and sets back."""
    system, X0 = _system(T)
    xs, ys = ss.simulate(system, X0, T, rng)
    posteriors = ss.classical_filter(system, X0, ys)
    last = posteriors[-1]
    last.interval_hull()                       # a queried set must still pickle on its way back
    return {"x": xs, "posterior": last, "system": system,
            "contains_truth": bool(last.contains(xs[-1]))}


def _system(T: int):
    A = np.array([[0.9, 0.2], [-0.1, 0.8]])
    W = ss.ConstrainedZonotope(0.2 * np.array([[1.0, -0.5, 0.3], [0.2, 0.4, -0.6]]), np.zeros(2),
                               np.array([[1.0, 1.0, 1.0]]), np.array([0.5]))
    u = np.tile([[0.1, 0.0]], (T, 1))          # a known input, B = I: added to x_(k+1) as it is
    system = ss.LinearSystem(A, B=np.eye(2), C=np.array([[1.0, 0.0]]), W=W,
                             V=ss.Box([-0.1], [0.1]), u=u)
    return system, ss.Box([-1, -1], [1, 1])


def kill_once(rng: np.random.Generator, marker: str, log: str) -> float:
    """A run that takes its worker process down the first time any run sees ``marker``."""
    value = float(rng.standard_normal())
    time.sleep(0.02)
    try:
        os.remove(marker)            # exactly one run (cluster-wide) succeeds in removing it
    except FileNotFoundError:
        pass
    else:
        os._exit(1)                  # the worker dies mid-task; the nanny starts a new one
    with open(log, "a") as f:        # one line per completed execution
        f.write(f"{value!r}\n")
    return value


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=":0", silence_logs=40)
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def test_cluster_results_equal_serial_bit_for_bit(client):
    serial = run(draw, 200, seed=11, executor="serial", progress=False)
    on_cluster = run(draw, 200, seed=11, executor=client, progress=False)
    assert len(on_cluster) == 200
    for a, b in zip(serial, on_cluster):
        assert a.tobytes() == b.tobytes()


def test_sets_systems_and_results_travel_through_dask(client):
    trial = functools.partial(filter_trial, T=8)
    serial = run(trial, 4, seed=3, executor="serial", progress=False)
    on_cluster = run(trial, 4, seed=3, executor=client, progress=False)
    for a, b in zip(serial, on_cluster):
        assert a["x"].tobytes() == b["x"].tobytes()
        assert a["contains_truth"] and b["contains_truth"]
        hull_a, hull_b = a["posterior"].interval_hull(), b["posterior"].interval_hull()
        np.testing.assert_allclose(hull_b.lo, hull_a.lo, rtol=0, atol=1e-9)
        np.testing.assert_allclose(hull_b.hi, hull_a.hi, rtol=0, atol=1e-9)
        np.testing.assert_array_equal(b["system"].input_term(3), a["system"].input_term(3))
        pickle.loads(pickle.dumps(b))        # and they pickle again on this side


def test_worker_lost_mid_run_loses_and_duplicates_no_run(client, tmp_path: Path):
    marker, log = tmp_path / "kill-marker", tmp_path / "executions.log"
    marker.touch()
    trial = functools.partial(kill_once, marker=str(marker), log=str(log))
    serial_values = [float(np.random.default_rng(s).standard_normal())
                     for s in np.random.SeedSequence(5).spawn(40)]
    values = run(trial, 40, seed=5, executor=client, progress=False)
    assert not marker.exists(), "no worker was killed: the test proved nothing"
    assert values == serial_values                 # none lost, none duplicated, same order and bits
    executed = log.read_text().split()
    assert set(map(float, executed)) == set(serial_values)


def test_run_errors_reach_the_caller(client):
    with pytest.raises(ZeroDivisionError):
        run(functools.partial(_divide_by_zero_on_negative), 20, seed=0, executor=client, progress=False)


def _divide_by_zero_on_negative(rng: np.random.Generator) -> float:
    value = rng.standard_normal()
    return 1 / 0 if value < 0 else value


def _figure_numbers(path: Path) -> dict:
    import json

    data = json.loads(path.read_text())
    return {k: v for k, v in data.items() if k not in ("wall_time_s", "cpu_time_s")}


def test_figures_command_on_a_scheduler_equals_a_serial_run(client, tmp_path: Path):
    from setsmooth.runs import cli

    address = client.scheduler.address
    assert cli.main(["figures", "smoothing_fig6", "--runs", "20", "--no-progress",
                     "--scheduler", address, "--out", str(tmp_path / "dask")]) == 0
    assert cli.main(["figures", "smoothing_fig6", "--runs", "20", "--no-progress", "--workers", "1",
                     "--out", str(tmp_path / "local")]) == 0
    name = "smoothing_fig6.json"
    assert _figure_numbers(tmp_path / "dask" / name) == _figure_numbers(tmp_path / "local" / name)


def test_scheduler_and_workers_together_are_refused(capsys):
    from setsmooth.runs import cli

    with pytest.raises(SystemExit):
        cli.main(["figures", "--scheduler", "tcp://127.0.0.1:1", "--workers", "2"])
    assert "--workers" in capsys.readouterr().err


def test_progress_bar_advances_to_the_last_run_on_a_cluster(client, capsys):
    run(draw, 30, seed=1, executor=client, progress=True)
    err = capsys.readouterr().err
    assert "30/30" in err and "Monte Carlo" in err


def test_the_commands_report_an_unreachable_scheduler_with_status_2(monkeypatch, capsys):
    from setsmooth.runs import dask_cluster

    assert dask_cluster.scheduler_client(None, "setsmooth figures") == (None, 0)

    def refused(address):
        raise OSError(f"Timed out trying to connect to {address}")

    monkeypatch.setattr(dask_cluster, "connect", refused)
    assert dask_cluster.scheduler_client("tcp://nowhere:1", "setsmooth arena") == (None, 2)
    assert "setsmooth arena: --scheduler tcp://nowhere:1: Timed out" in capsys.readouterr().err
