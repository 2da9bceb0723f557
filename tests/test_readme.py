"""The README's Python snippets are part of the API contract: they must run as written."""

import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_snippets_run():
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    assert len(blocks) >= 2
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, str(README), "exec"), namespace)
    assert namespace["smoothed"][10].diameter(certified=True) <= \
        namespace["posteriors"][10].diameter(certified=True) + 1e-6
    # the quick start shows smoothing helping visibly: x_0's range shrinks to a quarter
    assert namespace["d_smooth"][0] < 0.3 * namespace["d_filt"][0]
