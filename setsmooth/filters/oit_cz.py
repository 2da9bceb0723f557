"""The OIT-CZ SMF (stability paper Algorithm 3): `oit_cz_filter`, its door, and the loop `run_oit_cz`.

Every interval hull the algorithm takes is certified (weak-duality upper bounds, `solvers.certify`), so
the boxes T̂^ō, P_o·IH and the radius ℓ_k that the later steps build on are outer bounds in floating
point; the windows' hulls keep one warm-started simplex model per direction and window structure
(`setsmooth.solvers.parametric.ParametricSupport`).
"""

from __future__ import annotations

import weakref
from time import process_time as perf_counter  # CPU time: robust on a shared machine
from typing import Any

import numpy as np

from .._validation import measured
from ..sets.base import ConvexSet

from ..results import SetEstimates
from ..sets.algebra import linear_map
from ..sets.empty import EmptySet
from ..solvers.parametric import ParametricSupport
from ._oit_support import Structure, upsilon_inf
from ._window import Window
from .consistency import check_on_inconsistent, outer_inconsistency, report_inconsistency
from .oit import OITResult, _check_int, _reset, _structure
from .steps import _check_state_set, _predict, _update

__all__ = ["oit_cz_filter", "run_oit_cz"]


def oit_cz_filter(system, X0: ConvexSet, ys: Any, *, delta_bar: int | None = None,
                  epsilon: float = 1e-3, decomposition=None, hulls: bool = False,
                  on_inconsistent: str = "warn") -> OITResult:
    """Stability paper Algorithm 3: the OIT-inspired constrained-zonotopic SMF (OIT-CZ SMF).

    Lines 2–6 (k < δ̄): the exact CZ filter (20)–(21) from X0, reset by Line 5 when empty (θ-doubling);
    Line 6 keeps the interval hull of the unobservable part of each prior. Lines 7–12 (k ≥ δ̄): the
    window Z_k = F_{k,k−δ̄}(P⁻¹(T̂^o × T̂^ō)) of (22)–(23), with T̂^o = ℝ^{n_o} for k < 2δ̄ (Lemma 1's θ̄
    = ∞) and P_o·IH(Z_{k−δ̄}) afterwards (footnote 19: the posterior's hull in place of the prior's),
    and T̂^ō the box of Line 6, then B_{α_k}[ĉ^ō_k] of Lines 9–12 with the paper's
    α_k = ½‖Ã_ō^{k−δ̄}‖∞ d∞(Z̃^ō_δ̄) + Υ∞ ℓ_{k−1} + ε.
    For observable (A, C) the window prior is ℝⁿ (T̂^o = ℝⁿ, nothing else remains): Z_k =
    F_{k,k−δ̄}(ℝⁿ), whose constraint matrix is the same at every step and only b changes.

    Parameters
    ----------
    system : LinearSystem
        Time-invariant A, C, E, F; W and V with CZ forms. A known input u is allowed (B, D may vary).
    X0 : ConvexSet
        Bounded initial condition with a CZ form.
    ys : array_like, shape (T+1, m)
    delta_bar : int, optional
        δ̄ ≥ k_* = max{μ_o − 1 + n_λ0, 1}; default n_o − rank(C̃_o) + 3 (the paper's runs), raised to
        k_* if smaller.
    epsilon : float
        ε > 0 of Line 12 (unused for observable systems).
    decomposition : optional
        An observability decomposition to use instead of computing one.
    hulls : bool
        Compute the certified interval hulls of every estimate during the run, timed apart
        (``result.hulls``, ``hull_seconds``). Without it ``result.lo``/``hi`` compute them on first
        use.
    on_inconsistent : {'warn', 'raise', 'ignore'}
        What to do when an estimate is empty, which no reset repairs. From δ̄ on every Z_k contains
        the exact posterior, so an empty Z_k proves the data inconsistent with the model (a non-empty
        one does not prove them consistent; `setsmooth.filters.consistency`); before δ̄ an empty
        estimate is reset (Line 5: the initial condition was wrong, not the model) unless no
        θ ≤ 2⁶⁰ gives a non-empty one. 'warn' issues a `ModelInvalidationWarning` naming the first
        such step, its measurement and its distance from the output set predicted from Z_{k−1};
        'raise' raises `ModelInvalidatedError`. Empty estimates are `EmptySet`s (NaN hull rows); for
        detectable systems, whose later windows are built from them, every later one too. Finding
        them costs one emptiness program per step when the hulls are not computed (observable
        systems without ``hulls=True``); 'ignore' skips it.

    Returns
    -------
    OITResult

    Raises
    ------
    ValueError
        On a time-varying system, sets without CZ form, δ̄ < k_*, ε ≤ 0 or an undetectable (A, C);
        `ModelInvalidatedError` (a ValueError) for inconsistent data with ``on_inconsistent='raise'``.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> box = ss.Box([-1.0], [1.0])
    >>> system = ss.LinearSystem([[1.0, 1.0], [0.0, 1.0]], None, [[1.0, 0.0]], E=[[0.5], [1.0]],
    ...                          W=box, V=box)
    >>> xs, ys = ss.simulate(system, ss.Box([1, 1], [3, 3]), 8, np.random.default_rng(0))
    >>> res = ss.oit_cz_filter(system, ss.Box([-1, -1], [1, 1]), ys, delta_bar=2)
    >>> len(res.estimates), all(Z.contains(x) for Z, x in zip(res.estimates[2:], xs[2:]))
    (9, True)
    """
    given, system, ys = system, *measured(system, ys)
    _check_state_set(X0, "X0", system.n)
    check_on_inconsistent(on_inconsistent)
    for name, S in (("X0", X0), ("system.W", system.W), ("system.V", system.V)):
        if S._flat_cz is None:
            raise ValueError(f"{name} must have a constrained-zonotope form for the OIT-CZ SMF, "
                             f"got {type(S).__name__}")
    st = _structure(system, decomposition)
    default = st.n_o - int(np.linalg.matrix_rank(st.C_o)) + 3 if st.n_o else 1
    delta_bar = max(default, st.k_star) if delta_bar is None else _check_int(delta_bar, "delta_bar",
                                                                             st.k_star)
    if isinstance(epsilon, bool) or not np.isfinite(epsilon) or not epsilon > 0:
        raise ValueError(f"epsilon must be a positive finite number, got {epsilon!r}")
    if not st.observable and max(abs(np.linalg.eigvals(st.A_obar))) >= 1:
        raise ValueError("(A, C) is not detectable: the unobservable part has an eigenvalue of modulus "
                         ">= 1, and Algorithm 3 needs a detectable pair")
    ups = 0.0 if st.observable else upsilon_inf(st.A_obar)
    result = run_oit_cz(system, X0.to_constrained_zonotope(), ys, st, delta_bar, float(epsilon), ups,
                        hulls, on_inconsistent != "ignore")
    if on_inconsistent != "ignore":
        found = outer_inconsistency(system, X0, ys, result.estimates, "OIT-CZ", given)
        report_inconsistency(found, on_inconsistent)
    return result


def run_oit_cz(system, X0, ys: np.ndarray, st: Structure, delta_bar: int, epsilon: float,
               upsilon: float, want_hulls: bool, check_empty: bool) -> OITResult:
    """Algorithm 3 on checked arguments. An empty estimate (an empty window: the data contradict the
    model) becomes an `EmptySet` with a NaN hull row; the hulls computed reveal it (support values
    −inf), and with ``check_empty`` an emptiness program per step decides it where none is computed.
    For a detectable system every later estimate is empty too (its windows start from this one's
    hull); so is every estimate from a step whose Line 5 reset finds no θ."""
    n, T, d = system.n, ys.shape[0] - 1, delta_bar
    eye2 = np.vstack([np.eye(n), -np.eye(n)])
    estimates, resets, thetas = [], [], {}
    lo, hi = np.full((T + 1, n), np.nan), np.full((T + 1, n), np.nan)
    alpha = np.full(T + 1, np.nan)
    c_obar_all = np.full((T + 1, n - st.n_o), np.nan)
    step_s, hull_s = np.zeros(T + 1), np.zeros(T + 1)
    detectable = not st.observable
    n_obar = n - st.n_o
    X0_obar = linear_map(st.P_obar, X0) if detectable else None
    line6: list[tuple[np.ndarray, np.ndarray]] = []  # T̂^ō_k of Line 6: (centre, half-widths), k < δ̄

    def result() -> OITResult:
        estimates.extend(EmptySet(n) for _ in range(len(estimates), T + 1))
        sets = SetEstimates(estimates, system=system, X0=X0, ys=ys, kind="OIT-CZ", outer=True)
        return OITResult(sets, resets, thetas, d, (lo, hi) if want_hulls else None, alpha, c_obar_all,
                         step_s, hull_s)

    # Lines 2–6: the exact CZ filter, reset when empty.
    Z = None
    for k in range(min(d, T + 1)):
        t0 = perf_counter()
        prior = X0 if k == 0 else _predict(system, k - 1, Z)
        Z = _update(system, k, prior, ys[k])
        if Z.is_empty():
            reset = _reset(system, ys, k, st, X0_obar)
            if reset is None:  # no θ: the data contradict the model
                return result()
            Z, prior, thetas[k] = reset
            resets.append(k)
        if detectable:
            line6.append(_hull(linear_map(st.P_obar, prior), _pm(np.eye(n_obar))))
        estimates.append(Z)
        t1 = perf_counter()
        if want_hulls:
            lo[k], hi[k] = _bounds(_support(Z, eye2), n)
        step_s[k], hull_s[k] = t1 - t0, perf_counter() - t1
    if T < d:
        return result()

    if not detectable:
        window, engine = _kept(system, st, d, "observable", lambda: _observable_parts(system, d, n, eye2))
        hulls = engine.session()  # this run's warm models (`ParametricSupport.session`)
        free = np.full(n, np.inf)
        for k in range(d, T + 1):
            t0 = perf_counter()
            c, b, h, charges = window.charged_data(ys, k, window.centred_prior(ys, k), free)
            estimates.append(window.estimate_from(c, b, h, **charges))
            t1 = perf_counter()
            empty = False
            if want_hulls:
                values = hulls.values(c, b, h, **charges)
                empty = bool(np.isneginf(values).any())
                if not empty:
                    lo[k], hi[k] = _bounds(values, n)
            step_s[k], hull_s[k] = t1 - t0, perf_counter() - t1
            if empty or (check_empty and not want_hulls and estimates[-1].is_empty()):
                estimates[-1] = EmptySet(n)
        return result()

    # Lines 7–12 for a detectable (A, C); every hull is part of the algorithm here (step time).
    U, Po, n_o = st.U, st.P_o, st.n_o
    # The window priors' centres are computed in floating point: their error, at most a few units of
    # roundoff of ‖U‖(‖P_o‖|c| + |ĉ|), is covered by padding every prior factor bound by this bound.
    cond = float(np.linalg.norm(U, 2) * max(1.0, np.linalg.norm(Po, 2)))
    pad_unit = 64.0 * n * np.finfo(float).eps * cond
    first, later = _kept(system, st, d, "detectable", lambda: _detectable_parts(system, st, d, eye2))
    # This run's warm models (`ParametricSupport.session`), one set per window structure.
    first, later = ((window, engine.session()) for window, engine in (first, later))
    BW = linear_map(system.E_at(0), system.W)
    win_c, win_r = _hull(linear_map(st.P_obar, BW), _pm(np.eye(n_obar)))  # IH(B̃_ō W)
    Aobar_power = np.eye(n_obar)
    ell_prev, c_obar, d_delta = 0.0, None, None
    ball: dict[int, tuple[np.ndarray, float]] = {}  # T̂^ō_k = B_α_k[ĉ^ō_k], k ≥ δ̄
    for k in range(d, T + 1):
        t0 = perf_counter()
        i = k - d
        if i < d:  # Line 8 with θ̄ = ∞ (Lemma 1) and T̂^ō_i of Line 6
            c_box, r_box = line6[i]
            window, hulls = first
            c_p = U @ np.concatenate([np.zeros(n_o), c_box])
            pad = pad_unit * float(np.abs(c_box).max(initial=0.0))
            h_p = np.concatenate([np.full(n_o, np.inf), r_box + pad])
        else:      # Line 8 with T̂^o = P_o·IH(Z_i) and T̂^ō_i = B_α_i[ĉ^ō_i]
            c_ball, a_ball = ball[i]
            window, hulls = later
            centre, radius = (hi[i] + lo[i]) / 2, (hi[i] - lo[i]) / 2
            c_p = U @ np.concatenate([Po @ centre, c_ball])
            pad = pad_unit * (float(np.abs(centre).max()) + float(np.abs(c_ball).max(initial=0.0)))
            h_p = np.concatenate([radius + _ulp(hi[i], lo[i]) + pad, np.full(n_obar, a_ball + pad)])
        c, b, h, charges = window.charged_data(ys, k, c_p, h_p)
        Zk = window.estimate_from(c, b, h, **charges)
        estimates.append(Zk)
        values = hulls.values(c, b, h, **charges)
        if np.isneginf(values).any():  # an empty window, and every later window starts from it
            estimates[-1] = EmptySet(n)
            step_s[k] = perf_counter() - t0
            return result()
        lo[k], hi[k] = _bounds(values[:2 * n], n)
        in_lo, in_hi = _bounds(values[2 * n:2 * n + 2 * n_obar], n_obar)
        # Line 9: IH(Ã_21 Z̃^o_k ⊕ B̃_ō W) = IH(Ã_21 Z̃^o_k) ⊕ IH(B̃_ō W).
        c_in = (in_lo + in_hi) / 2 + win_c
        g_in = (in_hi - in_lo) / 2 + win_r + _ulp(in_hi, in_lo)
        if k == d:  # ĉ^ō_δ̄ and d∞(Z̃^ō_δ̄) from the certified hull of P_ō Z_δ̄ (the first window's
            # engine carries the directions ±P_ō for this one step)
            ob_lo, ob_hi = _bounds(values[2 * n + 2 * n_obar:], n_obar)
            c_obar = (ob_lo + ob_hi) / 2
            d_delta = 2.0 * float(((ob_hi - ob_lo) / 2 + _ulp(ob_hi, ob_lo)).max())
        # Line 12 (the paper's α_k), then Lines 10–11.
        a_k = 0.5 * _inf_norm(Aobar_power) * d_delta + upsilon * ell_prev + epsilon
        alpha[k] = a_k
        c_obar_all[k] = c_obar
        ball[k] = (c_obar, a_k)
        ell_prev = max(float(g_in.max()), ell_prev)
        c_obar = st.A_obar @ c_obar + c_in
        Aobar_power = st.A_obar @ Aobar_power
        step_s[k] = perf_counter() - t0
    return result()


#: Windows and their hull engines, kept per system (weakly) so that repeated runs on one system (Monte
#: Carlo, benchmarks) build the matrices and the solver instance once.
_KEPT: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _kept(system, st: Structure, d: int, kind: str, build):
    key = (kind, d, st.U.tobytes(), st.n_o)
    per_system = _KEPT.setdefault(system, {})
    if key not in per_system:
        if len(per_system) > 8:
            per_system.clear()
        per_system[key] = build()
    return per_system[key]


def _observable_parts(system, d: int, n: int, eye2: np.ndarray):
    window = Window(system, d, np.eye(n))
    return window, ParametricSupport(window.G, window.A, eye2, window.free(n))


def _detectable_parts(system, st: Structure, d: int, eye2: np.ndarray):
    n_obar = system.n - st.n_o
    dirs = np.vstack([eye2, _pm(st.A_21 @ st.P_o)])  # Ã_21 Z̃^o_k = (Ã_21 P_o) Z_k
    first = Window(system, d, st.U)                                          # P⁻¹(ℝ^{n_o} × box)
    later = Window(system, d, st.U @ _block_diag(st.P_o, np.eye(n_obar)))  # P⁻¹(P_o·IH × B_α)
    first_dirs = np.vstack([dirs, _pm(st.P_obar)])  # + the hull of P_ō Z_δ̄ (Line 11, Line 12)
    return ((first, ParametricSupport(first.G, first.A, first_dirs, first.free(st.n_o))),
            (later, ParametricSupport(later.G, later.A, dirs, later.free(0))))


def _pm(L: np.ndarray) -> np.ndarray:
    return np.vstack([L, -L])


def _block_diag(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    out = np.zeros((a.shape[0] + b.shape[0], a.shape[1] + b.shape[1]))
    out[:a.shape[0], :a.shape[1]] = a
    out[a.shape[0]:, a.shape[1]:] = b
    return out


def _support(Z, D: np.ndarray) -> np.ndarray:
    return Z.support_many(D, certified=True)


def _bounds(values: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) from the support values of [L; −L]."""
    return -values[n:2 * n], values[:n]


def _hull(S, D: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre and half-widths of the certified interval hull of S (D = [I; −I]), rounded outward."""
    m = D.shape[0] // 2
    lo, hi = _bounds(_support(S, D), m)
    return (lo + hi) / 2, (hi - lo) / 2 + _ulp(hi, lo)


def _ulp(hi: np.ndarray, lo: np.ndarray) -> np.ndarray:
    """A few units in the last place of the bounds: centre ± half-width then covers [lo, hi] though
    (lo + hi)/2 and (hi − lo)/2 are rounded."""
    return 4.0 * np.spacing(np.maximum(np.abs(hi), np.abs(lo)))


def _inf_norm(M: np.ndarray) -> float:
    return float(np.abs(M).sum(axis=1).max()) if M.size else 0.0
