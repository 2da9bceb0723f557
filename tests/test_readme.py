"""The README and the documentation pages' Python snippets are part of the API contract: they run as
written, and the README stays within its word budget (issue 27)."""

import re
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
#: Pages of the documentation site whose ```python blocks run in order, one namespace a page (listed,
#: not globbed: a page may quote code that is not meant to run, such as names of an older release).
DOC_PAGES = [ROOT / "docs" / name for name in ("sets.md", "estimators.md", "arena.md")]
README_WORDS = 1500


def _python_blocks(path: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", path.read_text(encoding="utf-8"), re.S)


def test_readme_stays_within_its_word_budget():
    words = len(README.read_text(encoding="utf-8").split())      # as `wc -w` counts them
    assert words <= README_WORDS, f"README.md has {words} words, the budget is {README_WORDS}"


def test_the_readme_quick_start_runs_as_one_block():
    blocks = _python_blocks(README)
    assert len(blocks) == 1, "the README's quick start is one block; longer examples live in docs/"
    namespace: dict = {}
    exec(compile(blocks[0], str(README), "exec"), namespace)
    assert namespace["smoothed"][10].diameter(certified=True) <= \
        namespace["posteriors"][10].diameter(certified=True) + 1e-6
    # the quick start shows smoothing helping visibly: x_0's range shrinks to a quarter
    assert namespace["d_smooth"][0] < 0.3 * namespace["d_filt"][0]


@pytest.mark.parametrize("page", DOC_PAGES, ids=lambda p: p.name)
def test_a_documentation_page_runs_as_written(page):
    assert _python_blocks(page), f"{page.name} has no Python example"
    namespace: dict = {}
    for block in _python_blocks(page):
        exec(compile(block, str(page), "exec"), namespace)
