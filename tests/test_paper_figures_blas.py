"""The timed figure scripts record the BLAS threads that were in force while they timed, read back."""

from __future__ import annotations

import os

import matplotlib.pyplot as plt
import pytest
from threadpoolctl import threadpool_info, threadpool_limits


def _threads_now() -> dict[str, int]:
    return {i["filepath"]: i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}


@pytest.mark.parametrize("asked", [1, 2])
def test_table1_records_the_blas_threads_in_force_while_it_timed(figures, monkeypatch, tmp_path, asked):
    table1 = figures("stability_table1")
    seen: list[set[int]] = []
    measure = table1.measure

    def spying_measure(rng, n, T):
        seen.append(set(_threads_now().values()))  # what the solves below will use
        return measure(rng, n, T)

    monkeypatch.setattr(table1, "measure", spying_measure)
    monkeypatch.setattr(table1, "_plot", lambda *args: plt.figure(figsize=(1, 1)))
    # The surrounding process runs with another limit: the script's own must win, be recorded, and be
    # undone afterwards (in the libraries loaded before; one loaded inside keeps the script's count).
    with threadpool_limits(limits=3 - asked, user_api="blas"):
        before = _threads_now()
        data = table1.main(runs=1, seed=1, out=tmp_path, progress=False, dimensions=(10,), steps=3,
                           blas_threads=asked)
        after = _threads_now()
    # A library may hold fewer threads than asked (an OpenBLAS started on one thread cannot always grow):
    # what is recorded is what the solves had, whatever was asked.
    assert len(seen) == 1 and asked in seen[0]
    if asked == 1:
        assert seen == [{1}]
    assert data["blas"]["requested"] == asked
    assert data["blas"]["in_force"] == sorted(seen[0])
    assert {lib["threads"] for lib in data["blas"]["libraries"]} == seen[0]
    counts = "/".join(map(str, sorted(seen[0])))
    assert data["settings"]["BLAS threads in force (read back)"].startswith(f"{counts} (read back: ")
    assert {path: after[path] for path in before} == before


def test_limited_sets_the_environment_for_libraries_loaded_later_and_restores_it(figures, monkeypatch):
    blas = figures("_blas")
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "7")
    monkeypatch.delenv("MKL_NUM_THREADS", raising=False)
    with blas.limited(1) as libraries:
        assert os.environ["OPENBLAS_NUM_THREADS"] == os.environ["MKL_NUM_THREADS"] == "1"
        assert blas.thread_counts(libraries) == [1]
    assert os.environ["OPENBLAS_NUM_THREADS"] == "7"
    assert "MKL_NUM_THREADS" not in os.environ
