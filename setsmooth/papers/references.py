"""The four papers setsmooth implements, so that "smoothing paper (24)" in a docstring is checkable.

Docstrings, figures and the report cite a paper by its short name and its own equation numbers:
"smoothing paper (24)" is equation (24) of `PAPERS['smoothing']`.

Examples
--------
>>> import setsmooth as ss
>>> print(ss.references.cite("stability"))
Y. Cong, X. Wang, X. Zhou, "Stability of Linear Set-Membership Filters With Respect to Initial Conditions: An Observation-Information Perspective," Automatica, 2024. arXiv:2203.13966.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Reference", "PAPERS", "cite"]


@dataclass(frozen=True)
class Reference:
    """One paper: who wrote it, what it is called, where it appeared."""

    short_name: str
    authors: tuple[str, ...]
    title: str
    venue: str
    year: int
    identifier: str  # an arXiv number or a URL where the text can be read

    def __str__(self) -> str:
        return f'{", ".join(self.authors)}, "{self.title}," {self.venue}, {self.year}. {self.identifier}.'


PAPERS: dict[str, Reference] = {
    "smoothing": Reference(
        "smoothing", ("Y. Li", "Y. Cong", "X. Zhou", "J. Dong"), "Optimal Set-Membership Smoothing",
        "arXiv preprint", 2024, "arXiv:2410.09857"),
    "rethinking": Reference(
        "rethinking", ("Y. Cong", "X. Wang", "X. Zhou"),
        "Rethinking the Mathematical Framework and Optimality of Set-Membership Filtering",
        "IEEE Transactions on Automatic Control, vol. 67, no. 5, pp. 2544–2551", 2022, "arXiv:2004.04524"),
    "stability": Reference(
        "stability", ("Y. Cong", "X. Wang", "X. Zhou"),
        "Stability of Linear Set-Membership Filters With Respect to Initial Conditions: An "
        "Observation-Information Perspective", "Automatica", 2024, "arXiv:2203.13966"),
    "lsu": Reference(
        "lsu", ("L. Kuklišová Pavelková",), "Bayesian State Estimation Using Constrained Zonotopes",
        "conference proceedings, SCITEPRESS", 2023,
        "https://scitepress.org/publishedPapers/2023/122309/pdf/index.html"),
}


def cite(short_name: str) -> str:
    """The formatted reference of a paper by its short name ('smoothing', 'rethinking', 'stability', 'lsu').

    Raises
    ------
    KeyError
        For an unknown short name, listing the known ones.
    """
    try:
        return str(PAPERS[short_name])
    except KeyError:
        raise KeyError(f"no paper {short_name!r}; known: {sorted(PAPERS)}") from None
