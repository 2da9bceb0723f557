"""The rethinking paper's figure scripts, run small: they write their files and their numbers are sane."""

from __future__ import annotations

import numpy as np
import pytest

from tests.figure_helpers import written


def small(**kw):
    return {"seed": 5, "progress": False, "executor": "serial", **kw}


def test_fig1_law_of_total_range_and_bayes_rule_give_the_captions_intervals(figures, tmp_path):
    figures("rethinking_fig1").main(out=tmp_path, **small())
    saved = written(tmp_path, "rethinking_fig1")
    assert saved["marginal_y"] == pytest.approx([1.0, 5.0], abs=1e-7)
    assert saved["posterior"] == pytest.approx([1.0, 2.0], abs=1e-7)
    assert saved["likelihoods"]["1.5"] == pytest.approx([1.5, 3.5], abs=1e-7)
    assert saved["likelihoods"]["2.5"] == pytest.approx([2.5, 4.5], abs=1e-7)
    assert saved["paper"] == "rethinking"


def test_fig2_ratio_starts_at_one_and_algorithm2_stays_inside_both_ranges(figures, tmp_path):
    fig2, ex = figures("rethinking_fig2"), figures("_rethinking_examples")
    data = fig2.main(runs=6, out=tmp_path, n_samples=300, **small())
    saved = written(tmp_path, "rethinking_fig2")
    mean, exact = np.array(saved["mean_ratio"]), np.array(saved["mean_exact_ratio"])
    assert mean.shape == (ex.FIG2_T + 1,) and mean[0] == pytest.approx(1.0)
    assert np.all(mean <= exact + 1e-9) and np.all(exact <= 1 + 1e-9)       # inner approximation; Theorem 3
    assert mean[ex.FIG2_STEADY_FROM:].mean() < 0.95                            # the relation does help
    ours = {r["quantity"].split(" (")[0]: r["ours"] for r in data["rows"]}
    assert ours["true state outside the classical range, of runs×(T+1)"].startswith("0 of")
    assert any(r["paper"] == "≈ 84 %" for r in data["rows"])


def test_fig3_optimal_polygons_are_inside_classical_ones_and_paper_values_are_placed(figures, tmp_path):
    fig3, ex = figures("rethinking_fig3"), figures("_rethinking_examples")
    data = fig3.main(runs=3, out=tmp_path, **small())
    saved = written(tmp_path, "rethinking_fig3")
    ratios = {k: np.array(v) for k, v in saved["area_ratios"].items()}
    assert ratios["0"] == pytest.approx(1.0, abs=1e-6)
    assert np.all(ratios["10"] < 1) and np.all(ratios["20"] < ratios["10"] + 0.5)
    rows = {r["quantity"]: r["ours"] for r in data["rows"]}
    assert rows["optimal posterior ⊆ classical posterior (Theorem 3): 64 support values, every run and k"] == "yes"
    assert any("is at quantile" in r["ours"] and r["paper"].startswith("27.1") for r in data["rows"])
    assert set(ex.PAPER_AREA_RATIOS) == {10, 20}


def test_fig3_check_bounds_equal_the_support_values_they_replace(figures):
    # The Theorem-3 check bounds h_optimal from above by the optimal walk's half-planes and h_classical
    # from below by the classical polygon's vertices, instead of 64 support solves per set: on these
    # polytopes both equal the solved support values to rounding, and each is on its safe side.
    import setsmooth as ss
    from setsmooth.papers.rethinking_examples import (rethinking_example_30, rethinking_example_30_joint_range,
                                                      rethinking_example_30_x0)
    from setsmooth.sets.vertices_2d import boundary_walk

    fig3 = figures("rethinking_fig3")
    system = rethinking_example_30()
    _, ys = fig3.simulate(np.random.default_rng(3), 20)
    classical = ss.classical_filter(system, rethinking_example_30_x0(), ys)
    for k in (0, 10, 20):
        optimal = ss.joint_trajectory_set(system, rethinking_example_30_joint_range(20), ys, k).project(
            [2 * k, 2 * k + 1])
        for S, bound, side in ((classical[k], fig3.inner_support(fig3.polygon(classical[k]), fig3.DIRECTIONS), 1),
                               (optimal, fig3.outer_support(*boundary_walk(optimal)[1:]), -1)):
            solved = S.support_many(fig3.DIRECTIONS)
            scale = np.abs(solved).max()
            assert bound == pytest.approx(solved, rel=0, abs=1e-9 * scale)
            assert np.all(side * (bound - solved) <= 1e-13 * scale)      # below / above, up to rounding
        assert np.array_equal(boundary_walk(optimal)[0], fig3.polygon(optimal))
    box = ss.Box([149.0, -1.0], [150.0, 0.0])
    assert fig3.inner_support(fig3.polygon(box), fig3.DIRECTIONS) == pytest.approx(
        box.support_many(fig3.DIRECTIONS), rel=1e-12)
    assert np.all(fig3.inner_support(np.zeros((0, 2)), fig3.DIRECTIONS) == -np.inf)
    assert np.all(fig3.outer_support(np.zeros((0, 2)), np.zeros(0)) == -np.inf)


def test_fig3_polygon_is_the_hull_of_the_boundary_points(figures):
    import setsmooth as ss

    fig3 = figures("rethinking_fig3")
    square = ss.Box([149.0, -1.0], [150.0, 0.0])
    assert fig3.area(fig3.polygon(square)) == pytest.approx(1.0, rel=1e-9)


def test_rethinking_report_has_its_title_and_preamble(figures, tmp_path):
    figures("rethinking_fig1").main(out=tmp_path, **small())
    report = figures("report").main(tmp_path).read_text()
    assert "## Rethinking paper" in report and "[1, 2 − w_(k−1)]" in report
