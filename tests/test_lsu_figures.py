"""The LSU paper's table and figure scripts, run small: files written, numbers sane, one shared experiment."""

from __future__ import annotations

import numpy as np

from tests.figure_helpers import written

SMALL = {"seed": 1, "progress": False, "executor": "serial", "K_values": (3.0, 0.0), "horizon": 15}


def test_tables_and_figures_share_one_experiment_and_report_every_published_value(figures, tmp_path):
    tables = figures("lsu_tables")
    data = tables.main(runs=2, out=tmp_path, **SMALL)
    saved = written(tmp_path, "lsu_tables")
    assert saved["paper"] == "lsu" and saved["settings"]["runs"] == 2
    assert saved["settings"]["experiment computed"] == "in this script"
    mean = np.array(saved["table1"]["mean"])
    assert mean.shape == (2, 6) and np.all(np.isfinite(mean)) and np.all(mean > 0)
    # one row per K and table with the published numbers beside ours
    t1 = [r for r in data["rows"] if r["quantity"].startswith("Table 1")]
    assert [r["paper"] for r in t1] == ["6 / 6.5 / 1.4 / 2.5", "50.3 / 141.7 / 250.8 / 181.5"]
    outside = [r for r in data["rows"] if r["quantity"].startswith("true state outside")][0]
    assert outside["ours"] == "0 / 0 / 0 / 0"
    assert len(list(tmp_path.glob("lsu_experiment_*.npz"))) == 1
    for name in ("lsu_fig1", "lsu_fig2", "lsu_fig3"):
        figures(name).main(runs=2, out=tmp_path, **SMALL)
        fig = written(tmp_path, name)
        assert fig["settings"]["experiment computed"] == "read from cache"
        assert len(fig["mean"]) == 2
    # the figures plot the tables' numbers; LSUCZ-1/2 share one support, hence one STD
    np.testing.assert_allclose(written(tmp_path, "lsu_fig1")["mean"], saved["table1"]["mean"])
    std = np.array(written(tmp_path, "lsu_fig3")["mean"])
    np.testing.assert_allclose(std[:, 0], std[:, 1])


def test_complexity_sweep_reports_errors_for_each_budget(figures, tmp_path):
    sweep = figures("lsu_complexity")
    data = sweep.main(runs=1, out=tmp_path, seed=2, progress=False, executor="serial", horizon=25,
                      K_values=(2.0,), budgets=((5, 1, "iter"), (9, 2, "iter")))
    saved = written(tmp_path, "lsu_complexity")
    assert np.array(saved["rmse_steady"]).shape == (1, 2)
    assert all(r["ours"] for r in data["rows"])


def test_the_experiment_cut_into_one_task_per_noise_level_gives_the_runs_over_all_levels(figures, tmp_path):
    ex = figures("_lsu_examples")
    exp = ex.experiment(2, 1, tmp_path, progress=False, executor="serial", K_values=(3.0, 0.0), horizon=15)
    from setsmooth import montecarlo

    whole = montecarlo.run(lambda rng: ex.trial(rng, K_values=(3.0, 0.0), horizon=15), 2, 1,
                           executor="serial", progress=False)
    for key in ("metrics", "outside"):
        assert np.array_equal(exp[key], np.array([r[key] for r in whole]))
