"""The report's verdict table follows the numbers the figure scripts record, with its stated thresholds."""

from __future__ import annotations

import json


def test_a_value_within_two_standard_errors_or_ten_percent_is_reproduced(figures):
    v = figures("_verdicts")
    assert v.verdict(v.value("radius", 13.0, 14.89, 1.0))[0] == v.REPRODUCED        # 1.9 ≤ 2 s.e.
    assert v.verdict(v.value("radius", 13.6, 14.89))[0] == v.REPRODUCED             # 8.7 % ≤ 10 %
    assert v.verdict(v.value("radius", 13.0, 14.89, 0.5))[0] == v.DIFFERS           # 1.9 > 1.0 and > 10 %
    assert v.verdict(v.value("radius", 13.0, 14.89, 0.5, rel_tol=0.2))[0] == v.REPRODUCED


def test_a_value_off_the_band_is_qualitative_only_when_its_stated_shape_holds(figures):
    v = figures("_verdicts")
    kept = v.value("speed-up", [22.0, 61.0], [1456.0, 6350.0], shape="faster as n grows", shape_holds=True)
    lost = v.value("speed-up", [22.0, 61.0], [1456.0, 6350.0], shape="faster as n grows", shape_holds=False)
    decided, reason = v.verdict(kept)
    assert decided == v.QUALITATIVELY and "faster as n grows holds" in reason and "2 of 2 outside" in reason
    assert v.verdict(lost)[0] == v.DIFFERS
    assert v.verdict(v.value("nan", float("nan"), 1.0, shape="x", shape_holds=None))[0] == v.DIFFERS


def test_claims_and_missing_and_schematic_items_appear_in_the_table(figures, tmp_path):
    v = figures("_verdicts")
    report = figures("report")
    data = {"paper": "stability", "figure": "Stability paper Fig. 2", "rows": [], "settings": {"runs": 1},
            "checks": [v.claim("David's estimate empty at k = 2", True, "ours: k = 2", "none"),
                       v.claim("gaps 0 from k = 6", False, "ours: k = 7", "none")]}
    (tmp_path / "stability_fig2.json").write_text(json.dumps(data))
    text = report.main(tmp_path).read_text()
    table = text[text.index("## Verdicts"):text.index("## Stability paper")]
    assert "| stability | Fig. 2: David's estimate empty at k = 2 | **reproduced** | ours: k = 2 | none |" in table
    assert "| stability | Fig. 2: gaps 0 from k = 6 | **differs** |" in table
    assert "| stability | Table 1 | missing | no `stability_table1.json` in this directory | — |" in table
    assert "| stability | Fig. 1 | not numerical |" in table and "| smoothing | Fig. 2 | not numerical |" in table
