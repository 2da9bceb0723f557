"""The stability paper's figure scripts, run small (the authors' trajectories cut at k = 10)."""

from __future__ import annotations

import numpy as np
import pytest

from tests.figure_helpers import written


def test_matlab_rand_replay_is_column_major(figures):
    ex = figures("_stability_examples")
    rs = np.random.RandomState(7)
    flat = np.random.RandomState(7).random_sample(6)
    M = ex.matlab_rand(rs, 2, 3)
    assert M.shape == (2, 3) and M[1, 0] == flat[1] and M[0, 1] == flat[2]


def test_authors_trajectories_follow_the_model_and_start_in_the_true_set(figures):
    ex = figures("_stability_examples")
    for example in (ex.EXAMPLE_25, ex.EXAMPLE_26):
        xs, ys = ex.authors_data(example)
        system = example.system()
        assert xs.shape == (51, 2) and ys.shape == (51, 1)
        assert np.all((xs[0] >= 1) & (xs[0] <= 3))
        w = np.linalg.lstsq(system.E_at(0), (xs[1:] - xs[:-1] @ system.A_at(0).T).T, rcond=None)[0]
        assert np.allclose(system.E_at(0) @ w, (xs[1:] - xs[:-1] @ system.A_at(0).T).T) and np.all(np.abs(w) <= 1)
        assert np.all(np.abs(ys - xs @ system.C_at(0).T) <= 1)


def test_fig2_small_reproduces_the_published_claims(figures, tmp_path):
    fig2 = figures("stability_fig2")
    data = fig2.main(runs=2, out=tmp_path, seed=1, progress=False, executor="serial", horizon=10)
    saved = written(tmp_path, "stability_fig2")
    rows = {r["quantity"]: r["ours"] for r in data["rows"]}
    assert rows["David's estimate becomes empty at k"] == "2"
    assert rows["Alice, Bob, Carol: estimation gap 0 from k (exact Hausdorff ≤ 1e-6)"] == "Alice 5, Bob 5, Carol 5"
    assert rows["k = 1: Carol ⊃ Bob ⊃ Alice ⊃ true posterior"].startswith("yes")
    gap = np.array(saved["Alice"]["gap"], dtype=float)
    surrogate = np.array(saved["Alice"]["gap_surrogate"], dtype=float)
    assert np.all(surrogate >= gap - 1e-7)                            # the surrogate bounds the gap
    assert saved["bound_16"]["delta"] == 1
    assert np.all(np.array(saved["OIT"]["diameter"][2:]) <= saved["bound_16"]["oit_delta_2"] + 1e-9)
    assert len(saved["fresh_runs"]["David"]["first_empty"]) == 1
    assert [r["quantity"] for r in data["rows"]] == [r["quantity"] for r in saved["rows"]]


def test_fig3_small_gaps_halve_every_step(figures, tmp_path):
    fig3 = figures("stability_fig3")
    data = fig3.main(runs=1, out=tmp_path, progress=False, executor="serial", horizon=10)
    saved = written(tmp_path, "stability_fig3")
    rows = {r["quantity"]: r["ours"] for r in data["rows"]}
    assert rows["David's estimate becomes empty at k (diameter 0 from then on)"] == "2"
    for name in ("Alice", "Bob", "Carol"):
        gap = np.array(saved[name]["gap"], dtype=float)
        assert np.all(gap[4:] <= 0.55 * gap[3:-1])                   # ρ(Ã_ō) = 0.5
    assert saved["upsilon_inf"]["value"] == pytest.approx(2.0, abs=1e-5)


def test_horizon_is_checked(figures, tmp_path):
    with pytest.raises(ValueError, match="horizon must be an integer in \\[10, 50\\]"):
        figures("stability_fig2").main(out=tmp_path, horizon=5)
