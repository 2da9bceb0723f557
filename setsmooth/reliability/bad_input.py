"""Bad input at the door (issue 7): one probe per public entry point that takes numbers and one bad value.

Each probe is one call with one bad argument, which must be refused with a ValueError/TypeError/IndexError
whose message names the argument as the user passed it. ``names`` is a regular expression the message must
match: the argument's own name (``A(2)`` for a callable evaluated at k = 2, ``A[2]`` for a sequence,
``u[3]``), never an internal one ("M", "translation vector"). Complex input is a TypeError everywhere:
NumPy's float cast would silently drop the imaginary part. ``tests/test_bad_input.py`` checks every probe;
``benchmarks/bad_input_census.py`` classifies them (clear / naming the wrong thing / deep traceback /
silently accepted).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import scipy.sparse as sp

import setsmooth as ss
from setsmooth.filters.interval import IntervalEstimates

__all__ = ["Probe", "PROBES"]


@dataclass(frozen=True)
class Probe:
    """One public call with one bad argument: the exception it must raise, and what its message names."""

    id: str
    call: Callable[[], object]
    exc: type | tuple
    names: str  # a regular expression the message must match


PROBES: list[Probe] = []


def add(id: str, call, exc, names: str) -> None:
    PROBES.append(Probe(id, call, exc, names))


# -- fixtures of the probes (built lazily: a probe must fail in its own call, not at import) --------
S1, C1 = np.sin(1.0), np.cos(1.0)
A31 = np.array([[S1, C1], [-C1, S1]])
E31, C31, F31 = np.array([[0.5], [1.0]]), np.array([[0.5, 0.5], [1.0, 0.3]]), np.eye(2)
B2, D2 = np.eye(2), 0.1 * np.eye(2)  # a known input u (zero) entering the state and the measurements
HERMITIAN = np.array([[2.0, 1j], [-1j, 2.0]])
CPLX2 = np.array([1.0 + 1e-3j, 0.0])
T_PROBE = 5


def system(**over) -> ss.LinearSystem:
    args = dict(A=A31, B=B2, C=C31, D=D2, E=E31, F=F31, W=ss.Box([-1.0], [1.0]),
                V=ss.Box([-1.0, -1.0], [1.0, 1.0]), u=np.zeros((T_PROBE + 1, 2)))
    args.update(over)
    return ss.LinearSystem(**args)


def bad_at(k_bad: int, good, bad):
    """A callable of k returning ``good`` except at k = k_bad."""
    return lambda k: bad if k == k_bad else good


def ys_probe(T: int = T_PROBE) -> np.ndarray:
    return np.random.default_rng(0).uniform(-1, 1, (T + 1, 2))


def x0_box() -> ss.Box:
    return ss.Box([-5, -5], [5, 5])


def sets() -> dict[str, ss.ConvexSet]:
    return {
        "Box": ss.Box([0, 0], [1, 1]),
        "Zonotope": ss.Zonotope(np.eye(2), np.zeros(2)),
        "CZ": ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[0.5]),
        "Ellipsoid": ss.Ellipsoid([0.0, 0.0], np.eye(2)),
        "HPolytope": ss.HPolytope(np.vstack([np.eye(2), -np.eye(2)]), np.ones(4)),
    }


# -- set constructors ------------------------------------------------------------------------------
for _id, _call, _exc, _names in [
    ("Box-lo-complex", lambda: ss.Box(CPLX2, [1, 1]), TypeError, r"\blo\b"),
    ("Box-hi-complex", lambda: ss.Box([0, 0], [1 + 1j, 1]), TypeError, r"\bhi\b"),
    ("Box-lo-strings", lambda: ss.Box(["0", "0"], [1, 1]), TypeError, r"\blo\b"),
    ("Box-hi-nan", lambda: ss.Box([0, 0], [1, np.nan]), ValueError, r"\bhi\b"),
    ("Zonotope-G-complex", lambda: ss.Zonotope(np.eye(2) * (1 + 1j), [0, 0]), TypeError, r"\bG\b"),
    ("Zonotope-c-complex", lambda: ss.Zonotope(np.eye(2), CPLX2), TypeError, r"\bc\b"),
    ("Zonotope-G-sparse-complex", lambda: ss.Zonotope(sp.csc_matrix(np.eye(2) * 1j), [0, 0]), TypeError,
     r"\bG\b"),
    ("Zonotope-G-inf", lambda: ss.Zonotope([[1, np.inf], [0, 1]], [0, 0]), ValueError, r"\bG\b"),
    ("Zonotope-G-ragged", lambda: ss.Zonotope([[1, 0], [1]], [0, 0]), (TypeError, ValueError), r"\bG\b"),
    ("CZ-G-complex", lambda: ss.ConstrainedZonotope(np.eye(2) * 1j, [0, 0]), TypeError, r"\bG\b"),
    ("CZ-c-complex", lambda: ss.ConstrainedZonotope(np.eye(2), CPLX2), TypeError, r"\bc\b"),
    ("CZ-A-complex", lambda: ss.ConstrainedZonotope(np.eye(2), [0, 0], A=[[1j, 1]], b=[0]), TypeError,
     r"\bA\b"),
    ("CZ-b-complex", lambda: ss.ConstrainedZonotope(np.eye(2), [0, 0], A=[[1, 1]], b=[1j]), TypeError,
     r"\bb\b"),
    ("CZ-h-complex", lambda: ss.ConstrainedZonotope(np.eye(2), [0, 0], h=[1, 1j]), TypeError, r"\bh\b"),
    ("CZ-h-scalar-complex", lambda: ss.ConstrainedZonotope(np.eye(2), [0, 0], h=2j), TypeError, r"\bh\b"),
    ("CZ-G-sparse-complex", lambda: ss.ConstrainedZonotope(sp.csc_matrix(np.eye(2) * 1j), [0, 0]),
     TypeError, r"\bG\b"),
    ("CZ-A-sparse-complex", lambda: ss.ConstrainedZonotope(
        sp.csc_matrix(np.eye(2)), [0, 0], A=sp.csc_matrix([[1j, 1.0]]), b=[0]), TypeError, r"\bA\b"),
    ("CZ-h-strings", lambda: ss.ConstrainedZonotope(np.eye(2), [0, 0], h=["1", "1"]), TypeError, r"\bh\b"),
    ("HPolytope-H-complex", lambda: ss.HPolytope([[1j, 0]], [1]), TypeError, r"\bH\b"),
    ("HPolytope-k-complex", lambda: ss.HPolytope([[1, 0]], [1j]), TypeError, r"\bk\b"),
    ("HPolytope-k-nan", lambda: ss.HPolytope([[1, 0]], [np.nan]), ValueError, r"\bk\b"),
    ("Ellipsoid-Q-hermitian", lambda: ss.Ellipsoid([0, 0], HERMITIAN), TypeError, r"\bQ\b"),
    ("Ellipsoid-c-complex", lambda: ss.Ellipsoid(CPLX2, np.eye(2)), TypeError, r"\bc\b"),
    ("Ellipsoid-Q-nan", lambda: ss.Ellipsoid([0, 0], [[1, np.nan], [np.nan, 1]]), ValueError, r"\bQ\b"),
    ("Reals-n-float", lambda: ss.Reals(2.5), TypeError, r"\bn\b"),
    ("Reals-n-complex", lambda: ss.Reals(2 + 0j), TypeError, r"\bn\b"),
    ("EmptySet-n-float", lambda: ss.EmptySet(2.0), TypeError, r"\bn\b"),
    ("LinearMap-M-complex", lambda: ss.LinearMap(np.eye(2) * 1j, ss.Box([0, 0], [1, 1])), TypeError,
     r"\bM\b"),
    ("LinearMap-offset-complex", lambda: ss.LinearMap(np.eye(2), ss.Box([0, 0], [1, 1]), CPLX2),
     TypeError, r"\boffset\b"),
    ("IntervalEstimates-lo-complex", lambda: IntervalEstimates([0j, 1], [1, 2]), TypeError, r"\blo\b"),
]:
    add(_id, _call, _exc, _names)


# -- queries and operators, on every representation ------------------------------------------------
ORIGIN = np.zeros(2)
_QUERIES = [
    ("support-d-complex", lambda S: S.support(CPLX2), TypeError, r"\bd\b"),
    ("support-d-nan", lambda S: S.support([np.nan, 1.0]), ValueError, r"\bd\b"),
    ("support-d-inf", lambda S: S.support([np.inf, 1.0]), ValueError, r"\bd\b"),
    ("support-d-length", lambda S: S.support([1.0, 0.0, 0.0]), ValueError, r"\bd\b"),
    ("support-d-strings", lambda S: S.support(["1", "0"]), TypeError, r"\bd\b"),
    ("support_many-D-complex", lambda S: S.support_many(np.eye(2) * (1 + 1j)), TypeError, r"\bD\b"),
    ("support_many-D-nan", lambda S: S.support_many([[np.nan, 1.0]]), ValueError, r"\bD\b"),
    ("support_many-D-shape", lambda S: S.support_many(np.ones((2, 3))), ValueError, r"\bD\b"),
    ("support_point-d-complex", lambda S: S.support_point(CPLX2), TypeError, r"\bd\b"),
    ("contains-point-complex", lambda S: S.contains(CPLX2), TypeError, r"\bpoint\b"),
    ("contains-point-nan", lambda S: S.contains([np.nan, 0.0]), ValueError, r"\bpoint\b"),
    ("contains-tol-complex", lambda S: S.contains(ORIGIN, tol=1e-6j), TypeError, r"\btol\b"),
    ("contains-tol-numpy-complex", lambda S: S.contains(ORIGIN, tol=np.complex128(1e-6)), TypeError,
     r"\btol\b"),
    ("contains-tol-nan", lambda S: S.contains(ORIGIN, tol=np.nan), ValueError, r"\btol\b"),
    ("contains-tol-negative", lambda S: S.contains(ORIGIN, tol=-1.0), ValueError, r"\btol\b"),
    ("contains-tol-string", lambda S: S.contains(ORIGIN, tol="0.1"), TypeError, r"\btol\b"),
    ("center-reference-complex", lambda S: S.center("closest", reference=CPLX2), TypeError,
     r"\breference\b"),
    ("project-dims-float", lambda S: S.project([0.5]), TypeError, r"\bdims\b"),
    ("project-dims-complex", lambda S: S.project([1j]), TypeError, r"\bdims\b"),
    ("project-dims-range", lambda S: S.project([5]), ValueError, r"\bdims\b"),
    ("matmul-M-complex", lambda S: (np.eye(2) * 1j) @ S, TypeError, r"\bM\b"),
    ("matmul-M-sparse-complex", lambda S: sp.csc_matrix(np.eye(2) * 1j) @ S, TypeError, r"\bM\b"),
    ("matmul-M-nan", lambda S: np.array([[1.0, np.nan]]) @ S, ValueError, r"\bM\b"),
    ("matmul-M-shape", lambda S: np.ones((2, 3)) @ S, ValueError, r"\bM\b"),
    ("add-vector-complex", lambda S: S + CPLX2, TypeError, r"translation vector"),
    ("sub-vector-complex", lambda S: S - CPLX2, TypeError, r"translation vector"),
    ("add-vector-nan", lambda S: S + np.array([np.nan, 0.0]), ValueError, r"translation vector"),
    ("intersect_preimage-R-complex", lambda S: S.intersect_preimage([[1j, 0]], ss.Box([0], [1])),
     TypeError, r"\bR\b"),
    ("intersect_preimage-R-nan", lambda S: S.intersect_preimage([[np.nan, 0]], ss.Box([0], [1])),
     ValueError, r"\bR\b"),
    ("intersect_preimage-Y-type", lambda S: S.intersect_preimage([[1, 0]], [0, 1]), TypeError, r"\bY\b"),
    ("preimage-M-complex", lambda S: S.preimage(np.eye(2) * 1j), TypeError, r"\bM\b"),
    ("preimage-M-inf", lambda S: S.preimage([[np.inf, 0], [0, 1]]), ValueError, r"\bM\b"),
    ("sample-rng-int", lambda S: S.sample(42), TypeError, r"\brng\b"),
]

for _set_name in ("Box", "Zonotope", "CZ", "Ellipsoid", "HPolytope"):
    for _id, _query, _exc, _names in _QUERIES:
        add(f"{_set_name}.{_id}", (lambda name, query: lambda: query(sets()[name]))(_set_name, _query),
            _exc, _names)


# -- LinearSystem construction ---------------------------------------------------------------------
for _id, _call, _exc, _names in [
    ("LinearSystem-A-complex", lambda: system(A=A31 * (1 + 1j)), TypeError, r"\bA\b"),
    ("LinearSystem-B-complex", lambda: system(B=B2 * 1j), TypeError, r"\bB\b"),
    ("LinearSystem-E-complex", lambda: system(E=E31 * 1j), TypeError, r"\bE\b"),
    ("LinearSystem-F-complex", lambda: system(F=F31 * 1j), TypeError, r"\bF\b"),
    ("LinearSystem-C-complex", lambda: system(C=C31 + 1e-9j), TypeError, r"\bC\b"),
    ("LinearSystem-D-complex", lambda: system(D=D2 * 1j), TypeError, r"\bD\b"),
    ("LinearSystem-A-nan", lambda: system(A=[[np.nan, 0], [0, 1]]), ValueError, r"\bA\b"),
    ("LinearSystem-B-inf", lambda: system(B=[[np.inf, 0], [0, 1]]), ValueError, r"\bB\b"),
    ("LinearSystem-E-inf", lambda: system(E=[[np.inf], [1]]), ValueError, r"\bE\b"),
    ("LinearSystem-F-nan", lambda: system(F=[[np.nan, 0], [0, 1]]), ValueError, r"\bF\b"),
    ("LinearSystem-C-nan", lambda: system(C=[[np.nan, 0], [0, 1]]), ValueError, r"\bC\b"),
    ("LinearSystem-D-nan", lambda: system(D=[[np.nan, 0], [0, 1]]), ValueError, r"\bD\b"),
    ("LinearSystem-A-strings", lambda: system(A=[["1", "0"], ["0", "1"]]), TypeError, r"\bA\b"),
    ("LinearSystem-A-sequence-complex", lambda: system(A=[A31, A31 * 1j, A31]), TypeError, r"A\[1\]"),
    ("LinearSystem-A-sequence-nan", lambda: system(A=[A31, A31, A31 * np.nan]), ValueError, r"A\[2\]"),
    ("LinearSystem-A-sequence-shapes", lambda: system(A=[A31, np.eye(3)]), ValueError, r"A\[1\]|\bA\b"),
    ("LinearSystem-B-sequence-nan", lambda: system(B=[B2, B2 * np.nan]), ValueError, r"B\[1\]"),
    ("LinearSystem-E-sequence-nan", lambda: system(E=[E31, E31 * np.nan]), ValueError, r"E\[1\]"),
    ("LinearSystem-A-callable-complex", lambda: system(A=lambda k: A31 * 1j), TypeError, r"A\(0\)"),
    ("LinearSystem-A-callable-nan", lambda: system(A=lambda k: A31 * np.nan), ValueError, r"A\(0\)"),
    ("LinearSystem-A-callable-shape", lambda: system(A=lambda k: np.ones((2, 3))), ValueError, r"A\(0\)|\bA\b"),
    ("LinearSystem-C-callable-complex", lambda: system(C=lambda k: C31 * 1j), TypeError, r"C\(0\)"),
    ("LinearSystem-D-callable-nan", lambda: system(D=lambda k: D2 * np.nan), ValueError, r"D\(0\)"),
    ("LinearSystem-F-callable-nan", lambda: system(F=lambda k: F31 * np.nan), ValueError, r"F\(0\)"),
    ("LinearSystem-E-vs-W", lambda: system(W=ss.Box([-1, -1], [1, 1])), ValueError, r"\bE\b"),
    ("LinearSystem-F-vs-V", lambda: system(V=ss.Box([-1], [1])), ValueError, r"\bF\b"),
    ("LinearSystem-W-type", lambda: system(W=[-1, 1]), TypeError, r"\bW\b"),
    ("LinearSystem-u-complex", lambda: system(u=np.ones((5, 2)) * 1j), TypeError, r"\bu\b"),
    ("LinearSystem-u-row-nan", lambda: system(u=np.vstack([np.zeros((3, 2)), [[np.nan, 0]], np.zeros((1, 2))])),
     ValueError, r"u\[3\]"),
    ("LinearSystem-u-row-inf", lambda: system(u=[[0, 0], [np.inf, 0]]), ValueError, r"u\[1\]"),
    ("LinearSystem-u-shape", lambda: system(u=np.ones((5, 3))), ValueError, r"\bu\b"),
    ("LinearSystem-u-strings", lambda: system(u=[["0", "0"]]), TypeError, r"\bu\b"),
    ("from_statespace-F-complex", lambda: ss.LinearSystem.from_statespace(
        _statespace(), W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), noise_inputs=[0], F=[[1j]]), TypeError, r"\bF\b"),
    ("from_statespace-dt-complex", lambda: ss.LinearSystem.from_statespace(
        _statespace(dt=0), W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), noise_inputs=[0], dt=0.1j), TypeError,
     r"\bdt\b"),
    ("from_statespace-dt-nan", lambda: ss.LinearSystem.from_statespace(
        _statespace(dt=0), W=ss.Box([-1], [1]), V=ss.Box([-1], [1]), noise_inputs=[0], dt=np.nan), ValueError,
     r"\bdt\b"),
]:
    add(_id, _call, _exc, _names)


def _statespace(dt=1):
    import control

    return control.StateSpace([[0.9, 0.1], [0.0, 0.8]], [[1.0], [0.5]], [[1.0, 0.0]], [[0.0]], dt)


# -- values computed at step k, seen by every estimator --------------------------------------------
_AT_STEP = {
    "A(2)-nan": (dict(A=bad_at(2, A31, A31 * np.nan)), ValueError, r"A\(2\)"),
    "A(2)-complex": (dict(A=bad_at(2, A31, A31 + 1e-3j)), TypeError, r"A\(2\)"),
    "A(2)-shape": (dict(A=bad_at(2, A31, A31.reshape(-1))), ValueError, r"A\(2\)"),
    "B(2)-inf": (dict(B=bad_at(2, B2, np.full((2, 2), np.inf))), ValueError, r"B\(2\)"),
    "E(2)-inf": (dict(E=bad_at(2, E31, E31 * np.inf)), ValueError, r"E\(2\)"),
    "C(2)-nan": (dict(C=bad_at(2, C31, C31 * np.nan)), ValueError, r"C\(2\)"),
    "D(2)-shape": (dict(D=bad_at(2, D2, np.eye(3))), ValueError, r"D\(2\)"),
    "F(2)-shape": (dict(F=bad_at(2, F31, np.eye(3))), ValueError, r"F\(2\)"),
    "u(3)-nan": (dict(u=bad_at(3, np.zeros(2), np.array([np.nan, 0.0]))), ValueError, r"u\(3\)"),
    "u(3)-complex": (dict(u=bad_at(3, np.zeros(2), CPLX2)), TypeError, r"u\(3\)"),
    "u(3)-length": (dict(u=bad_at(3, np.zeros(2), np.zeros(3))), ValueError, r"u\(3\)"),
}

# Set estimators are queried too: a bad value that slipped in would reach the solver there.
_ESTIMATORS = {
    "classical_filter": lambda sys: ss.classical_filter(sys, x0_box(), ys_probe())[-1].interval_hull(),
    "smoother-recursion": lambda sys: ss.optimal_smoother(sys, x0_box(), ys_probe(),
                                                          method="recursion")[0].interval_hull(),
    "smoother-trajectory": lambda sys: ss.optimal_smoother(sys, x0_box(), ys_probe(),
                                                           method="trajectory")[0].interval_hull(),
    "trajectory_set": lambda sys: ss.trajectory_set(sys, x0_box(), ys_probe()).interval_hull(),
    "simulate": lambda sys: ss.simulate(sys, x0_box(), T_PROBE, np.random.default_rng(0)),
    "kalman_filter": lambda sys: ss.kalman_filter(sys, ys_probe(), np.zeros(2), np.eye(2), 1.0, 1.0),
    "rts_smoother": lambda sys: ss.rts_smoother(sys, ys_probe(), np.zeros(2), np.eye(2), 1.0, 1.0),
}

for _bad, (_over, _exc, _names) in _AT_STEP.items():
    for _est, _run in _ESTIMATORS.items():
        add(f"{_est}-{_bad}", (lambda over, run: lambda: run(system(**over)))(_over, _run), _exc, _names)


# -- estimator arguments ---------------------------------------------------------------------------
def _nonlinear(f=None, g=None, n=1):
    return ss.NonlinearSystem(f or (lambda k, x, w: np.cbrt(x) + x + w), g or (lambda k, x, v: 2 * x + v),
                              ss.Box([-1], [1]), ss.Box([1], [3]), n=n)


def _interval_ys(T=4):
    return np.linspace(0.0, 1.0, T + 1)


def _meas(k, y):
    return ((y - 3) / 2, (y - 1) / 2)


def _filtered():
    return ss.interval_filter(lambda x: np.cbrt(x) + x, [-1, 1], [-5, 5], _interval_ys(), _meas)


for _id, _call, _exc, _names in [
    ("simulate-T-float", lambda: ss.simulate(system(), x0_box(), 2.5, np.random.default_rng(0)),
     (TypeError, ValueError), r"\bT\b"),
    ("simulate-T-complex", lambda: ss.simulate(system(), x0_box(), 3 + 0j, np.random.default_rng(0)),
     (TypeError, ValueError), r"\bT\b"),
    ("simulate-x0-complex", lambda: ss.simulate(system(), x0_box(), 3, np.random.default_rng(0), x0=CPLX2),
     TypeError, r"\bx0\b"),
    ("simulate-x0-nan", lambda: ss.simulate(system(), x0_box(), 3, np.random.default_rng(0),
                                            x0=[np.nan, 0]), ValueError, r"\bx0\b"),
    ("simulate-x0-outside", lambda: ss.simulate(system(), x0_box(), 3, np.random.default_rng(0),
                                                x0=[6.0, 0.0]), ValueError, r"\bx0\b"),
    ("simulate-x0-length", lambda: ss.simulate(system(), x0_box(), 3, np.random.default_rng(0),
                                               x0=[0.0, 0.0, 0.0]), ValueError, r"\bx0\b"),
    ("simulate-x0_set-dim", lambda: ss.simulate(system(), ss.Box([-1], [1]), 3, np.random.default_rng(0)),
     ValueError, r"\bx0_set\b"),
    ("simulate-rng-float", lambda: ss.simulate(system(), x0_box(), 3, 42.0), TypeError, r"\brng\b"),
    ("NonlinearSystem-n-float", lambda: _nonlinear(n=2.5), TypeError, r"\bn\b"),
    ("NonlinearSystem-n-zero", lambda: _nonlinear(n=0), ValueError, r"\bn\b"),
    ("NonlinearSystem-n-complex", lambda: _nonlinear(n=1 + 0j), TypeError, r"\bn\b"),
    ("NonlinearSystem-f-complex", lambda: ss.simulate(_nonlinear(f=lambda k, x, w: x + 1j), ss.Box([-1], [1]),
                                                      3, np.random.default_rng(0)), TypeError, r"\bf\("),
    ("NonlinearSystem-f-nan", lambda: ss.simulate(_nonlinear(f=lambda k, x, w: x * np.nan), ss.Box([-1], [1]),
                                                  3, np.random.default_rng(0)), ValueError, r"\bf\("),
    ("NonlinearSystem-f-shape", lambda: ss.simulate(_nonlinear(f=lambda k, x, w: np.zeros(3)),
                                                    ss.Box([-1], [1]), 3, np.random.default_rng(0)),
     ValueError, r"\bf\("),
    ("NonlinearSystem-g-complex", lambda: ss.simulate(_nonlinear(g=lambda k, x, v: x * 1j), ss.Box([-1], [1]),
                                                      3, np.random.default_rng(0)), TypeError, r"\bg\("),
    ("classical_filter-ys-complex", lambda: ss.classical_filter(system(), x0_box(), ys_probe() * 1j),
     TypeError, r"\bys\b"),
    ("classical_filter-ys-nan", lambda: ss.classical_filter(system(), x0_box(), ys_probe() * np.nan),
     ValueError, r"\bys\b"),
    ("classical_filter-ys-shape", lambda: ss.classical_filter(system(), x0_box(), np.ones((4, 3))),
     ValueError, r"\bys\b"),
    ("classical_filter-ys-strings", lambda: ss.classical_filter(system(), x0_box(), [["1", "2"]]),
     TypeError, r"\bys\b"),
    ("classical_filter-X0-dim", lambda: ss.classical_filter(system(), ss.Box([0], [1]), ys_probe()),
     ValueError, r"\bX0\b"),
    ("optimal_smoother-ys-complex", lambda: ss.optimal_smoother(system(), x0_box(), ys_probe() * 1j),
     TypeError, r"\bys\b"),
    ("trajectory_set-ys-complex", lambda: ss.trajectory_set(system(), x0_box(), ys_probe() + 0j),
     TypeError, r"\bys\b"),
    ("kalman_filter-x0_mean-complex", lambda: ss.kalman_filter(system(), ys_probe(), CPLX2, np.eye(2), 1, 1),
     TypeError, r"\bx0_mean\b"),
    ("kalman_filter-P0-hermitian", lambda: ss.kalman_filter(system(), ys_probe(), np.zeros(2), HERMITIAN, 1, 1),
     TypeError, r"\bP0\b"),
    ("kalman_filter-P0-nan", lambda: ss.kalman_filter(system(), ys_probe(), np.zeros(2), np.eye(2) * np.nan,
                                                      1, 1), ValueError, r"\bP0\b"),
    ("kalman_filter-Q-complex", lambda: ss.kalman_filter(system(), ys_probe(), np.zeros(2), np.eye(2), 1j, 1),
     TypeError, r"\bQ\b"),
    ("kalman_filter-Q-numpy-complex", lambda: ss.kalman_filter(system(), ys_probe(), np.zeros(2), np.eye(2),
                                                               np.complex128(1), 1), TypeError, r"\bQ\b"),
    ("kalman_filter-Q-string", lambda: ss.kalman_filter(system(), ys_probe(), np.zeros(2), np.eye(2), "1", 1),
     TypeError, r"\bQ\b"),
    ("kalman_filter-Q-nan", lambda: ss.kalman_filter(system(), ys_probe(), np.zeros(2), np.eye(2), np.nan, 1),
     ValueError, r"\bQ\b"),
    ("kalman_filter-R-hermitian", lambda: ss.kalman_filter(system(), ys_probe(), np.zeros(2), np.eye(2), 1,
                                                           HERMITIAN), TypeError, r"\bR\b"),
    ("kalman_filter-ys-complex", lambda: ss.kalman_filter(system(), ys_probe() * 1j, np.zeros(2), np.eye(2),
                                                          1, 1), TypeError, r"\bys\b"),
    ("rts_smoother-P0-hermitian", lambda: ss.rts_smoother(system(), ys_probe(), np.zeros(2), HERMITIAN, 1, 1),
     TypeError, r"\bP0\b"),
    ("interval_filter-w_interval-complex", lambda: ss.interval_filter(
        lambda x: np.cbrt(x) + x, [-1, 1j], [-5, 5], _interval_ys(), _meas), TypeError, r"\bw_interval\b"),
    ("interval_filter-w_interval-nan", lambda: ss.interval_filter(
        lambda x: np.cbrt(x) + x, [-1, np.nan], [-5, 5], _interval_ys(), _meas), ValueError,
     r"\bw_interval\b"),
    ("interval_filter-x0_interval-complex", lambda: ss.interval_filter(
        lambda x: np.cbrt(x) + x, [-1, 1], [-5j, 5], _interval_ys(), _meas), TypeError, r"\bx0_interval\b"),
    ("interval_filter-ys-complex", lambda: ss.interval_filter(
        lambda x: np.cbrt(x) + x, [-1, 1], [-5, 5], _interval_ys() * 1j, _meas), TypeError, r"\bys\b"),
    ("interval_filter-ys-nan", lambda: ss.interval_filter(
        lambda x: np.cbrt(x) + x, [-1, 1], [-5, 5], _interval_ys() * np.nan, _meas), ValueError, r"\bys\b"),
    ("interval_filter-eta-complex", lambda: ss.interval_filter(
        lambda x: x + 1j, [-1, 1], [-5, 5], _interval_ys(), _meas), TypeError, r"\beta\b"),
    ("interval_filter-measurement_interval-complex", lambda: ss.interval_filter(
        lambda x: np.cbrt(x) + x, [-1, 1], [-5, 5], _interval_ys(), lambda k, y: (1j, 2)), TypeError,
     r"measurement_interval"),
    ("interval_smoother-w_interval-complex", lambda: ss.interval_smoother(
        lambda x: np.cbrt(x) + x, [-1j, 1], _filtered()), TypeError, r"\bw_interval\b"),
    ("interval_smoother-eta-complex", lambda: ss.interval_smoother(
        lambda x: np.cbrt(x) + x + 0j, [-1, 1], _filtered()), TypeError, r"\beta\b"),
    ("interval_smoother-eta_inverse-complex", lambda: ss.interval_smoother(
        lambda x: np.cbrt(x) + x, [-1, 1], _filtered(), eta_inverse=lambda v: v + 1j), TypeError,
     r"\beta_inverse\b"),
    ("montecarlo-n_runs-float", lambda: ss.montecarlo.run(_trial, 2.5, 0, executor="serial", progress=False),
     TypeError, r"\bn_runs\b"),
    ("montecarlo-n_runs-complex", lambda: ss.montecarlo.run(_trial, 2j, 0, executor="serial",
                                                            progress=False), TypeError, r"\bn_runs\b"),
    ("montecarlo-seed-complex", lambda: ss.montecarlo.run(_trial, 2, 1j, executor="serial", progress=False),
     TypeError, r"\bseed\b"),
    ("montecarlo-seed-negative", lambda: ss.montecarlo.run(_trial, 2, -1, executor="serial", progress=False),
     ValueError, r"\bseed\b"),
    ("montecarlo-workers-float", lambda: ss.montecarlo.run(_trial, 2, 0, workers=1.5, progress=False),
     TypeError, r"\bworkers\b"),
]:
    add(_id, _call, _exc, _names)


def _trial(rng):
    return float(rng.uniform())
