"""One set, many representations: random CZs re-represented by 1e±12 scalings, checked against HiGHS.

Three re-representations of Z = Z(G, c, A, b, h) (random, 1–2 constraints, see `random_cz`), each entry
of the scaling drawn from {1e-12, 1, 1e12} (at least one not 1):

* ``rows``: constraint row r multiplied by s_r: (A, b) → (S A, S b). The same set.
* ``factors``: factor j replaced by ξ_j/s_j: G e_j → s_j G e_j, A e_j → s_j A e_j, h_j → h_j/s_j. The
  same set (the constraint column scales with the generator column).
* ``coordinates``: Z' = M Z with M = diag(s) (G → MG, c → Mc). Not the same set, but its answers
  are those of Z transformed: h_{Z'}(d') = h_Z(Mᵀd') so we query d' = M⁻ᵀd and compare with h_Z(d),
  and M p ∈ Z' for p ∈ Z.

The exact values come from `oracle.cz_support` on the *unscaled* Z. Per set and solver path ('auto':
closed form or fast path; 'generic': CVXPY), over 2·dim axis and 4 random directions and two members
(an interior point G ξ* + c and a polished support point, i.e. a boundary point):

* **wrong**: a finite value off by more than ``REL_TOL · σ_d``, σ_d = |dᵀc| + Σ_j |(Gᵀd)_j| h_j (the
  zonotope-hull magnitude along d, the same for every representation); a certified value above the
  exact one by more than that also counts;
* **inf**: ``inf`` (or ``-inf``, i.e. "empty") for a bounded direction of a nonempty set;
* **rejected**: ``contains`` returned False for a member;
* **certified below**: a certified value below the exact one by more than ``CERT_TOL · σ_d`` (the
  oracle's accuracy; auto path only, the generic path cannot certify);
* **SolverError**: acceptable (counted apart, with the status); any other exception is a finding.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import setsmooth as ss

from .oracle import cz_support, factor_form
from .random_systems import case_rng, random_cz

HOWS = ("rows", "factors", "coordinates")
PATHS = ("auto", "generic")
REL_TOL = 1e-6
CERT_TOL = 1e-9
SCALES = (1e-12, 1.0, 1e12)


@dataclass(frozen=True, eq=False)
class Rescaled:
    """A CZ and one re-representation of it (see the module docstring)."""

    name: str
    how: str
    original: ss.ConstrainedZonotope
    scaled: ss.ConstrainedZonotope
    M: np.ndarray        # scaled = M · original as sets (identity unless how == 'coordinates')
    factors: np.ndarray  # the scalings applied (rows, factors or coordinates)


@dataclass
class RescaleOutcome:
    """Counts of one rescaled set on one path."""

    name: str
    how: str
    path: str
    queries: int = 0
    wrong: int = 0
    worst_wrong: float = 0.0
    inf: int = 0
    rejected: int = 0
    certified_below: int = 0
    worst_certified_below: float = 0.0
    solver_errors: list[str] = field(default_factory=list)
    other_errors: list[str] = field(default_factory=list)

    @property
    def silent_failure(self) -> bool:
        return bool(self.wrong or self.inf or self.rejected or self.certified_below or self.other_errors)


def _draw(rng: np.random.Generator, size: int) -> np.ndarray:
    s = rng.choice(SCALES, size)
    if np.all(s == 1.0):
        s[rng.integers(size)] = rng.choice([1e-12, 1e12])
    return s


def rescale(Z: ss.ConstrainedZonotope, how: str, s: np.ndarray, name: str) -> Rescaled:
    """Re-represent ``Z`` by the scalings ``s`` of its rows, factors or coordinates."""
    f = factor_form(Z)
    M = np.eye(Z.dim)
    if how == "rows":
        scaled = ss.ConstrainedZonotope(f.G, f.c, f.A * s[:, None], f.b * s, f.h)
    elif how == "factors":
        scaled = ss.ConstrainedZonotope(f.G * s, f.c, f.A * s, f.b, f.h / s)
    elif how == "coordinates":
        M = np.diag(s)
        scaled = ss.ConstrainedZonotope(M @ f.G, M @ f.c, f.A, f.b, f.h)
    else:
        raise ValueError(f"how must be one of {HOWS}, got {how!r}")
    return Rescaled(name, how, Z, scaled, M, s)


def rewrite(rng: np.random.Generator, kind: str, k: float, G, c, A, b, h
            ) -> tuple[ss.ConstrainedZonotope, np.ndarray]:
    """Z(G, c, A, b, h) with its constraint rows, factors or coordinates scaled by 10^U(−k, k).

    Returns the CZ and σ: the same set for 'rows' and 'factors' (σ = 1), diag(σ)·Z for 'coordinates'.
    The scalings are drawn continuously, where `rescale` takes them from `SCALES`.
    """
    n, ng = G.shape
    sigma = np.ones(n)
    G2, c2, A2, b2, h2 = G, c, A, b, h
    if kind == "rows":
        r = 10.0 ** rng.uniform(-k, k, A.shape[0])
        A2, b2 = A * r[:, None], b * r
    elif kind == "factors":
        f = 10.0 ** rng.uniform(-k, k, ng)
        G2, A2, h2 = G * f, A * f, h / f
    else:
        sigma = 10.0 ** rng.uniform(-k, k, n)
        G2, c2 = G * sigma[:, None], c * sigma
    return ss.ConstrainedZonotope(G2, c2, A=A2, b=b2, h=h2), sigma


def random_rescalings(count: int, seed: int) -> list[Rescaled]:
    """``count`` rescaled random CZs (dim 2..4), cycling rows/factors/coordinates; the first is the
    issue's example CZ([[1, 1]], [0], [[1, −1]], [0.5]) with its row scaled by 1e-12."""
    out = [rescale(ss.ConstrainedZonotope([[1.0, 1.0]], [0.0], [[1.0, -1.0]], [0.5]), "rows",
                   np.array([1e-12]), "issue-example-rows")]
    for i in range(1, count):
        rng = case_rng(seed, 100_000 + i)
        Z = random_cz(rng, int(rng.integers(2, 5)))
        how = HOWS[i % len(HOWS)]
        size = {"rows": Z.nc, "factors": Z.ng, "coordinates": Z.dim}[how]
        out.append(rescale(Z, how, _draw(rng, size), f"{i:03d}-{how}"))
    return out


def _directions(dim: int, rng: np.random.Generator) -> np.ndarray:
    eye = np.eye(dim)
    return np.vstack([eye, -eye, rng.normal(size=(4, dim))])


def check(r: Rescaled, path: str, seed: int = 0) -> RescaleOutcome:
    """Query ``r.scaled`` on ``path`` and score it against the oracle on ``r.original``."""
    out = RescaleOutcome(r.name, r.how, path)
    rng = np.random.default_rng(seed)
    f = factor_form(r.original)
    D = _directions(r.original.dim, rng)
    exact, points = zip(*(cz_support(f, d) for d in D))
    exact = np.array(exact)
    DG = D @ f.G
    with np.errstate(invalid="ignore"):
        sigma = np.abs(D @ f.c) + np.where(DG == 0, 0.0, np.abs(DG) * f.h).sum(axis=1)
    Dq = D / np.diag(r.M)  # d' = M⁻ᵀ d (M diagonal)
    xi_star = np.linalg.lstsq(f.A, f.b, rcond=None)[0] if f.A.size else np.zeros(f.G.shape[1])
    members = [points[0]]
    if np.all(np.abs(xi_star) <= f.h):
        members.append(f.G @ xi_star + f.c)

    def run(label, call):
        try:
            return call()
        except ss.SolverError as exc:
            out.solver_errors.append(f"{label}: {exc.status}")
        except Exception as exc:  # noqa: BLE001 - an unexpected exception is a finding
            out.other_errors.append(f"{label}: {type(exc).__name__}: {str(exc)[:120]}")
        return None

    values = run("support", lambda: r.scaled.support_many(Dq, path=path))
    if values is not None:
        _score_values(out, values, exact, sigma, certified=False)
    if path == "auto":
        cert = run("certified", lambda: r.scaled.support_many(Dq, certified=True))
        if cert is not None:
            _score_values(out, cert, exact, sigma, certified=True)
    for p in members:
        inside = run("contains", lambda: r.scaled.contains(r.M @ p, path=path))
        out.queries += 1
        if inside is False:
            out.rejected += 1
    return out


def _score_values(out: RescaleOutcome, values, exact, sigma, certified: bool) -> None:
    values = np.asarray(values, dtype=float)
    out.queries += values.size
    finite = np.isfinite(values)
    out.inf += int((~finite).sum())
    err = values - exact
    bad = finite & (np.abs(err) > REL_TOL * sigma)
    if certified:
        below = finite & (err < -CERT_TOL * sigma)
        out.certified_below += int(below.sum())
        if below.any():
            out.worst_certified_below = max(out.worst_certified_below,
                                            float(np.max(-err[below] / sigma[below])))
        bad &= ~below  # counted once, as unsound
    out.wrong += int(bad.sum())
    if bad.any():
        out.worst_wrong = max(out.worst_wrong, float(np.max(np.abs(err[bad]) / sigma[bad])))


def describe(o: RescaleOutcome) -> str:
    parts = []
    if o.wrong:
        parts.append(f"{o.wrong} wrong finite values (worst {o.worst_wrong:.2e} of the scale)")
    if o.inf:
        parts.append(f"{o.inf} infinite values for bounded directions")
    if o.rejected:
        parts.append(f"{o.rejected} members rejected by contains")
    if o.certified_below:
        parts.append(f"{o.certified_below} certified values below exact (worst {o.worst_certified_below:.2e})")
    if o.other_errors:
        parts.append("exceptions: " + "; ".join(o.other_errors))
    return f"{o.name} [{o.path}]: " + ", ".join(parts)
