"""The paper-figure scripts, run small: they write their files and their numbers are sane."""

from __future__ import annotations

import json

import numpy as np
import pytest

from setsmooth.runs import cli
from tests.figure_helpers import written

TINY_GRID = (0.03, 0.3)


def small(**kw):
    return {"seed": 3, "progress": False, "executor": "serial", **kw}


def test_fig3_smoothed_hulls_are_inside_filtered_hulls_and_contain_the_truth(figures, tmp_path):
    fig3, ex = figures("smoothing_fig3"), figures("_smoothing_examples")
    data = fig3.main(runs=2, out=tmp_path, **small())
    saved = written(tmp_path, "smoothing_fig3")
    assert saved["settings"]["runs"] == 2 and len(saved["k"]) == ex.T + 1
    mean_f, mean_s = np.array(saved["mean_diameter_filtered"]), np.array(saved["mean_diameter_smoothed"])
    assert np.all(mean_s <= mean_f + ex.HULL_TOL)
    assert mean_s[-1] == pytest.approx(mean_f[-1], abs=ex.HULL_TOL)   # same set at k = T
    assert saved["outside_filtered"] == saved["outside_smoothed"] == 0
    assert saved["smoothed_le_filtered"] == [2 * (ex.T + 1)] * 2
    assert np.array(saved["fig3a"]["x"]).shape == (fig3.K_PLANE + 1, 2)
    assert [r["quantity"] for r in data["rows"]] == [r["quantity"] for r in saved["rows"]]


def test_fig4_best_pair_is_the_grid_minimum_and_fig5_reads_it(figures, tmp_path):
    fig4, fig5 = figures("smoothing_fig4"), figures("smoothing_fig5")
    grid = {"q_grid": TINY_GRID, "r_grid": TINY_GRID}
    fig4.main(runs=2, out=tmp_path, **small(**grid))
    saved = written(tmp_path, "smoothing_fig4")
    mse = np.array(saved["mse"])
    assert mse.shape == (2, 2) and np.all(np.isfinite(mse)) and np.all(mse > 0)
    assert saved["best_mse"] == pytest.approx(mse.min())
    assert (saved["best_q"], saved["best_r"]) in {(q, r) for q in TINY_GRID for r in TINY_GRID}
    assert saved["runs_per_pair"] == 2 and saved["settings"]["monte_carlo_seed"] == 3 + fig4.TUNING_SEED_OFFSET

    fig5.main(runs=2, out=tmp_path, **small(**grid))   # tunes with min(2, 100) runs: as fig4 did
    result = written(tmp_path, "smoothing_fig5")
    tuning = result["settings"]["rts_tuning"]
    assert tuning["source"].startswith("read from") and (tuning["q"], tuning["r"]) == (saved["best_q"], saved["best_r"])
    assert np.all(np.array(result["mse_sms"]) > 0) and np.all(np.array(result["mse_rts"]) > 0)


def test_fig5_recomputes_the_tuning_without_fig4_results(figures, tmp_path):
    fig5 = figures("smoothing_fig5")
    data = fig5.main(runs=1, out=tmp_path, **small(q_grid=TINY_GRID, r_grid=TINY_GRID))
    assert data["settings"]["rts_tuning"]["source"].startswith("recomputed")
    assert len(written(tmp_path, "smoothing_fig5")["mse_sms"]) == 51


def test_fig6_smoothed_intervals_are_inside_filtered_intervals(figures, tmp_path):
    fig6 = figures("smoothing_fig6")
    fig6.main(runs=30, out=tmp_path, **small())
    saved = written(tmp_path, "smoothing_fig6")
    mean_f, mean_s = np.array(saved["mean_diameter_filtered"]), np.array(saved["mean_diameter_smoothed"])
    assert np.all(mean_s[:-1] < mean_f[:-1]) and mean_s[-1] == mean_f[-1]
    assert np.all(mean_f <= 1 + 1e-12)   # (34) alone pins x_k to an interval of length 1
    assert saved["outside_filtered"] == saved["outside_smoothed"] == 0
    assert saved["smoothed_le_filtered"][0] == saved["smoothed_le_filtered"][1] == 30 * 51


def test_closed_form_eta_inverse_inverts_eta(figures):
    ex = figures("_smoothing_examples")
    for z in np.concatenate([np.linspace(-50, 50, 201), [0.0, 1e-12, -1e-9, 1e6, -1e8]]):
        assert ex.eta(ex.eta_inverse(z)) == pytest.approx(z, rel=1e-12, abs=1e-12)


def test_report_puts_paper_values_beside_ours(figures, tmp_path):
    figures("smoothing_fig6").main(runs=5, out=tmp_path, **small())
    report = figures("report").main(tmp_path).read_text()
    assert "smoothing_fig6" in report and "| quantity | paper | ours |" in report
    assert "smoothing_fig6.png" in report and "(paper: 5000)" in report


def test_cli_runs_a_figure_by_short_name_and_writes_the_report(tmp_path, capsys):
    assert cli.main(["figures", "fig6", "--runs", "4", "--out", str(tmp_path), "--no-progress",
                     "--workers", "1"]) == 0
    assert (tmp_path / "smoothing_fig6.png").exists() and (tmp_path / "REPORT.md").exists()
    assert json.loads((tmp_path / "smoothing_fig6.json").read_text())["settings"]["runs"] == 4
    assert "report" in capsys.readouterr().out


def test_cli_lists_the_smoothing_figures(capsys):
    assert cli.main(["figures", "--list"]) == 0
    listed = capsys.readouterr().out.split()
    assert {"smoothing_fig3", "smoothing_fig4", "smoothing_fig5", "smoothing_fig6"} <= set(listed)
    assert "report" not in listed and not any(name.startswith("_") for name in listed)


def test_cli_explains_a_missing_figures_directory(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv(cli.ENV_VAR, str(tmp_path))
    assert cli.main(["figures"]) == 2
    assert cli.ENV_VAR in capsys.readouterr().err


def test_cli_rejects_an_unknown_figure_name(capsys):
    assert cli.main(["figures", "fig99"]) == 2
    assert "matches no figure" in capsys.readouterr().err


def test_figure_names_resolve_exactly_or_by_a_unique_part():
    available = ["smoothing_fig3", "smoothing_fig4", "stability_fig3"]
    assert cli.select(available, []) == available
    assert cli.select(available, ["smoothing_fig3.py", "fig4"]) == ["smoothing_fig3", "smoothing_fig4"]
    with pytest.raises(ValueError, match="ambiguous"):
        cli.select(available, ["fig3"])


def test_report_groups_the_rows_by_paper(figures, tmp_path):
    def fake(paper, figure):
        return {"paper": paper, "figure": figure, "rows": [{"quantity": f"q of {figure}", "paper": 1,
                                                            "ours": 2}], "settings": {"runs": 1}}
    (tmp_path / "stability_fig9.json").write_text(json.dumps(fake("stability", "Stability Fig. 9")))
    (tmp_path / "smoothing_fig9.json").write_text(json.dumps(fake("smoothing", "Smoothing Fig. 9")))
    (tmp_path / "smoothing_fig8.json").write_text(json.dumps(fake("smoothing", "Smoothing Fig. 8")))
    report = figures("report").main(tmp_path).read_text()
    headings = sorted([(report.index("## Smoothing paper"), "smoothing"),
                       (report.index("## Stability paper"), "stability"),   # from _stability_examples.py
                       (len(report), None)])
    assert "Reproduction of the numerical section (IV-C) of the smoothing paper" in report  # its preamble

    def paper_of(figure):
        pos = report.index(f"### {figure}")
        return next(paper for (start, paper), (end, _) in zip(headings, headings[1:]) if start < pos < end)

    assert paper_of("Smoothing Fig. 8") == paper_of("Smoothing Fig. 9") == "smoothing"
    assert paper_of("Stability Fig. 9") == "stability"


def test_every_figure_script_follows_the_protocol(figures):
    import inspect

    for name in cli.discover(cli.find_figures_dir()):
        module = figures(name)
        assert module.NAME == name
        paper_module = figures(f"_{module.PAPER}_examples")          # the paper's shared settings
        assert paper_module.PAPER == module.PAPER and paper_module.REPORT_PREAMBLE
        assert name.startswith(f"{module.PAPER}_") and module.DEFAULT_RUNS >= 1
        params = inspect.signature(module.main).parameters
        assert {"runs", "seed", "out", "workers", "progress", "executor"} <= set(params)


def test_figure_json_names_its_paper(figures, tmp_path):
    figures("smoothing_fig6").main(runs=2, out=tmp_path, **small())
    saved = written(tmp_path, "smoothing_fig6")
    assert saved["paper"] == "smoothing" and saved["wall_time_s"] >= 0


def test_fig5_reads_fig3s_smoothed_hulls_and_gets_the_same_numbers(figures, tmp_path):
    fig3, fig5 = figures("smoothing_fig3"), figures("smoothing_fig5")
    grid = {"q_grid": TINY_GRID, "r_grid": TINY_GRID}
    alone = fig5.main(runs=2, out=tmp_path / "alone", **small(**grid))
    assert alone["settings"]["sms_source"].startswith("computed")
    fig3.main(runs=2, out=tmp_path / "both", **small())
    reused = fig5.main(runs=2, out=tmp_path / "both", **small(**grid))
    assert reused["settings"]["sms_source"].startswith("centres of the certified smoothed hulls")
    np.testing.assert_allclose(reused["mse_sms"], alone["mse_sms"], rtol=1e-9, atol=1e-12)
    np.testing.assert_array_equal(reused["mse_rts"], alone["mse_rts"])
    # Other settings: the saved runs are not used.
    assert fig3.load_runs(tmp_path / "both", 3, 3) is None and fig3.load_runs(tmp_path / "both", 2, 4) is None
