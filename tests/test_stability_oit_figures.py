"""Stability paper Fig. 4 and Table 1 (the OIT-CZ SMF), run small: files written, numbers sane."""

from __future__ import annotations

import numpy as np

from tests.figure_helpers import written


def test_fig4_oit_cz_estimates_stay_bounded_and_contain_the_truth(figures, tmp_path):
    fig4 = figures("stability_fig4")
    data = fig4.main(runs=1, seed=1, out=tmp_path, progress=False, executor="serial", n=4, T=14,
                     observable_p=(2,), detectable_no=(3,))
    saved = written(tmp_path, "stability_fig4")
    assert saved["paper"] == "stability" and saved["settings"]["T"] == 14
    for kind in ("observable", "detectable"):
        lo, hi, mean = (np.array(saved[f"{kind}_diameter_{s}"]) for s in ("min", "max", "mean"))
        assert lo.shape == (15,) and np.all(np.isfinite(hi)) and np.all((lo <= mean + 1e-12) & (mean <= hi + 1e-12))
        assert np.all(np.array(saved[f"{kind}_gap_max"]) <= np.array(saved[f"{kind}_diameter_max"]) + 1e-9)
    outside = [r["ours"] for r in data["rows"] if "outside the hull" in r["quantity"]]
    assert outside == [0, 0]


def test_table1_reports_every_filter_and_the_oit_radius_is_the_smallest(figures, tmp_path):
    table1 = figures("stability_table1")
    data = table1.main(runs=1, seed=2, out=tmp_path, progress=False, dimensions=(10,), steps=5)
    saved = written(tmp_path, "stability_table1")
    t = saved["table"]
    assert set(t) == {"girard", "combastel", "oit"}
    assert all(t[f]["outside"] == [0] for f in t)
    assert all(t[f]["step"][0] > 0 and t[f]["hull"][0] > 0 for f in t)  # speed: benchmarks/bench_oit.py
    assert t["oit"]["radius"][0] < t["girard"]["radius"][0]
    assert any("n = 10: hull radius" in r["quantity"] for r in data["rows"])
