"""Vector output of the paper figures: ``setsmooth figures --format pdf,svg``."""

import importlib
import os
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from setsmooth.runs import cli  # noqa: E402

FIGURES = Path(__file__).resolve().parents[1] / "paper_figures"


@pytest.fixture
def outputs(monkeypatch):
    monkeypatch.syspath_prepend(str(FIGURES))
    monkeypatch.delenv(cli.FORMATS_ENV, raising=False)
    return importlib.import_module("_outputs")


def _figure():
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1], label="a line")
    ax.set_title("tube widths")
    return fig


def test_write_outputs_writes_png_only_by_default(outputs, tmp_path):
    outputs.write_outputs(tmp_path, "demo", _figure(), {"x": 1})
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo.json", "demo.png"]


def test_write_outputs_adds_real_pdf_and_svg_files_when_asked(outputs, tmp_path, monkeypatch):
    monkeypatch.setenv(cli.FORMATS_ENV, "pdf,svg")
    outputs.write_outputs(tmp_path, "demo", _figure(), {"x": 1})
    assert (tmp_path / "demo.pdf").read_bytes().startswith(b"%PDF")
    svg = (tmp_path / "demo.svg").read_text()
    assert "<svg" in svg and "tube widths" in svg  # text kept as text (svg.fonttype none)
    assert (tmp_path / "demo.png").read_bytes().startswith(b"\x89PNG")


def test_format_lists_are_validated_with_the_known_formats_named():
    assert cli.parse_formats("PDF, .svg") == ["png", "pdf", "svg"]
    assert cli.parse_formats("") == ["png"]
    with pytest.raises(ValueError, match="choose from png, pdf, svg, eps"):
        cli.parse_formats("pdf,jpeg")


def test_cli_rejects_an_unknown_format(capsys):
    with pytest.raises(SystemExit):
        cli.main(["figures", "fig6", "--format", "tiff"])
    assert "unknown --format tiff" in capsys.readouterr().err


def test_cli_writes_vector_figures_and_restores_the_environment(tmp_path):
    assert cli.main(["figures", "fig6", "--runs", "2", "--out", str(tmp_path), "--no-progress",
                     "--workers", "1", "--format", "svg,pdf"]) == 0
    assert (tmp_path / "smoothing_fig6.pdf").read_bytes().startswith(b"%PDF")
    assert "<svg" in (tmp_path / "smoothing_fig6.svg").read_text()
    assert (tmp_path / "smoothing_fig6.png").exists() and (tmp_path / "REPORT.md").exists()
    assert cli.FORMATS_ENV not in os.environ
    sys.modules.pop("_outputs", None)
