"""Algorithm 2 (sampled optimal filter) and Algorithm 1 (classical interval filter) on example (27)–(28).

The oracle is the exact optimal range of (27)–(28) with ⟦v_k | w_{k−1}⟧ = [1, 2 − w_{k−1}] in closed
form: from a prior [a, b] and y > 0, x_k = η(x) + w with x ∈ [a, b], w ∈ [0, 1], x_k ≤ y (v ≥ 1) and
w ≤ 2 − y/x_k (v ≤ 2 − w). Since η is continuous and increasing, such x, w exist iff
max(0, x_k − η(b)) ≤ min(1, x_k − η(a), 2 − y/x_k), i.e.

    x_k ∈ [max(η(a), y/2, r₁), min(η(b) + 1, y, r₂)],   r₁,₂ the roots of x² − (2 + η(b)) x + y.
"""

from __future__ import annotations

import numpy as np
import pytest

import setsmooth as ss
from setsmooth.papers.rethinking_examples import eta_27, optimal_ranges_27, rethinking_example_27

SYSTEM = rethinking_example_27()
ROUND = 1e-12      # relative rounding slack when comparing endpoints computed two ways


def exact_step(a, b, y):
    """The exact range at k from [a, b] at k − 1 (y > 0) in closed form (module docstring)."""
    lo, hi = optimal_ranges_27_from(a, b, y)
    return lo, hi


def optimal_ranges_27_from(a, b, y):
    eb = eta_27(b)
    root = np.sqrt((2 + eb) ** 2 - 4 * y)
    return max(eta_27(a), y / 2, ((2 + eb) - root) / 2), min(eb + 1, y, ((2 + eb) + root) / 2)


def exact_filter(ys):
    lo, hi = np.full(len(ys), np.nan), np.full(len(ys), np.nan)
    lo[0], hi[0] = max(0.0, ys[0] / 2), min(1.0, ys[0])
    for k in range(1, len(ys)):
        lo[k], hi[k] = exact_step(lo[k - 1], hi[k - 1], ys[k])
    return lo, hi


def test_closed_form_optimal_step_matches_a_dense_grid_of_the_definition():
    """(29) by brute force: every (x_{k−1}, w) of a 1500² grid, kept when y/x_k ∈ [1, 2 − w]."""
    rng = np.random.default_rng(12)
    for _ in range(5):
        a = rng.uniform(0, 2)
        b = a + rng.uniform(0.05, 1)
        x_true = eta_27(rng.uniform(a, b)) + rng.uniform(0, 1)
        y = x_true * rng.uniform(1, 1.5)
        xp, w = np.meshgrid(np.linspace(a, b, 1500), np.linspace(0, 1, 1500))
        x = eta_27(xp) + w
        kept = x[(y / x >= 1) & (y / x <= 2 - w)]
        lo, hi = exact_step(a, b, y)
        assert lo <= kept.min() + 1e-12 and kept.max() <= hi + 1e-12
        assert kept.min() - lo < 2e-3 * (hi - lo) + 1e-3 and hi - kept.max() < 2e-3 * (hi - lo) + 1e-3


def test_library_closed_form_matches_this_one():
    xs, ys = SYSTEM.simulate(12, np.random.default_rng(13), runs=10)
    lo, hi = optimal_ranges_27(ys)
    for run in range(10):
        assert np.allclose(np.array(exact_filter(ys[run])), np.array([lo[run], hi[run]]), rtol=1e-13)


def inside(inner_lo, inner_hi, outer_lo, outer_hi):
    scale = 1 + np.abs(outer_hi)
    return np.all(inner_lo >= outer_lo - ROUND * scale) and np.all(inner_hi <= outer_hi + ROUND * scale)


def test_sampled_ranges_lie_inside_the_exact_optimal_and_the_classical_ranges():
    xs, ys = SYSTEM.simulate(15, np.random.default_rng(0), runs=30)
    sampled = ss.sampled_optimal_filter(SYSTEM, ys, np.random.default_rng(1), n_samples=2000)
    assert np.all(sampled.accepted[:, 1:] == 2000) and np.all(sampled.draws[:, 1:] >= 2000)
    for run in range(30):
        exact_lo, exact_hi = exact_filter(ys[run])
        classical = ss.classical_interval_filter(SYSTEM, ys[run])
        assert inside(sampled.lo[run], sampled.hi[run], exact_lo, exact_hi)
        assert inside(exact_lo, exact_hi, classical.lo, classical.hi)        # Theorem 3
        assert sampled.lo[run, 0] == exact_lo[0] and sampled.hi[run, 0] == exact_hi[0]  # k = 0 exact


def test_sampled_range_converges_to_the_optimal_range_as_n_grows():
    xs, ys = SYSTEM.simulate(1, np.random.default_rng(2), runs=40)
    exact = np.array([exact_step(max(0.0, y[0] / 2), min(1.0, y[0]), y[1]) for y in ys])
    gaps = {}
    for N in (100, 1000, 10_000):
        sampled = ss.sampled_optimal_filter(SYSTEM, ys, np.random.default_rng(N), n_samples=N)
        gap = (exact[:, 1] - exact[:, 0]) - sampled.lengths[:, 1]
        assert np.all(gap >= -ROUND)
        gaps[N] = gap.mean()
    assert gaps[10_000] < 0.5 * gaps[1000] < 0.25 * gaps[100]
    assert gaps[10_000] < 0.02 * (exact[:, 1] - exact[:, 0]).mean()   # ~N^(-1/2): the region has corners


def test_true_state_is_inside_the_classical_range_in_every_run():
    xs, ys = SYSTEM.simulate(20, np.random.default_rng(3), runs=300)
    for x, y in zip(xs, ys):
        classical = ss.classical_interval_filter(SYSTEM, y)
        assert np.all((classical.lo <= x) & (x <= classical.hi))


def test_papers_literal_reading_leaves_the_classical_range():
    """With ⟦v_k | w_{k−1}⟧ = [0, 2 − w_{k−1}] as printed, v_k < 1 puts x_k above y_k: outside [y/2, y]."""
    rng = np.random.default_rng(4)
    outside = 0
    for _ in range(50):
        x, w = rng.uniform(0, 1), rng.uniform(0, 1, 10)
        xs, ys = [x], [x * rng.uniform(1, 2)]
        for k in range(10):
            xs.append(eta_27(xs[-1]) + w[k])
            ys.append(xs[-1] * rng.uniform(0, 2 - w[k]))
        # data off the model: the range may also come out empty, which is what the warning would say
        classical = ss.classical_interval_filter(SYSTEM, np.array(ys), on_inconsistent="ignore")
        with np.errstate(invalid="ignore"):
            outside += int(np.sum(~((classical.lo <= xs) & (xs <= classical.hi))))
    assert outside > 0


@pytest.mark.parametrize("v_given_w, message", [
    (lambda w: (np.zeros_like(w), 2 - w), "leaves the marginal range"),        # the text's [0, 2 − w]
    (lambda w: (np.zeros_like(w), 1 - 2 * w), "is not an interval"),           # Algorithm 2's [0, 1 − 2w]
    (lambda w: (np.ones_like(w), 1.5 + 0 * w), "cover only"),
])
def test_conditional_ranges_breaking_the_law_of_total_range_are_refused(v_given_w, message):
    with pytest.raises(ValueError, match=message):
        ss.ScalarRelatedNoiseSystem(SYSTEM.eta, SYSTEM.measurement, SYSTEM.measurement_interval,
                                    (0, 1), (0, 1), (1, 2), v_given_w)


def test_simulated_noises_respect_the_conditional_range():
    xs, ys = SYSTEM.simulate(30, np.random.default_rng(5), runs=200)
    v = ys / xs
    w = xs[:, 1:] - eta_27(xs[:, :-1])
    assert np.all((w >= 0) & (w <= 1))
    assert np.all(v[:, 1:] >= 1 - 1e-12) and np.all(v[:, 1:] <= 2 - w + 1e-12)
    assert np.all((v[:, 0] >= 1 - 1e-12) & (v[:, 0] <= 2 + 1e-12))


def test_sampled_filter_is_reproducible_and_batching_runs_changes_nothing_but_the_stream():
    xs, ys = SYSTEM.simulate(5, np.random.default_rng(6), runs=3)
    a = ss.sampled_optimal_filter(SYSTEM, ys, np.random.default_rng(9), n_samples=300)
    b = ss.sampled_optimal_filter(SYSTEM, ys, np.random.default_rng(9), n_samples=300)
    assert np.array_equal(a.lo, b.lo) and np.array_equal(a.hi, b.hi)
    one = ss.sampled_optimal_filter(SYSTEM, ys[1], np.random.default_rng(9), n_samples=300)
    assert one.lo.shape == (1, 6) and isinstance(one[0], ss.IntervalEstimates)


def test_data_outside_every_consistent_state_give_empty_sampled_ranges():
    ys = np.array([[0.5, 50.0, 1.0]])    # y_1 = 50 needs x_1 ≥ 25, but x_1 ≤ η(1) + 1 < 3
    sampled = ss.sampled_optimal_filter(SYSTEM, ys, np.random.default_rng(0), n_samples=10, max_draws=2000)
    assert not np.isnan(sampled.lo[0, 0]) and np.isnan(sampled.lo[0, 1:]).all()
    assert sampled.accepted[0, 1] == 0 and sampled.draws[0, 1] == 2000


def test_sampled_filter_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="n_samples"):
        ss.sampled_optimal_filter(SYSTEM, [1.0, 1.0], np.random.default_rng(0), n_samples=0)
    with pytest.raises(TypeError, match="rng"):
        ss.sampled_optimal_filter(SYSTEM, [1.0, 1.0], 0)
    with pytest.raises(ValueError, match="max_draws"):
        ss.sampled_optimal_filter(SYSTEM, [1.0, 1.0], np.random.default_rng(0), n_samples=10, max_draws=5)
    with pytest.raises(ValueError, match="ys"):
        ss.sampled_optimal_filter(SYSTEM, np.ones((2, 2, 2)), np.random.default_rng(0))


def _rectangular_step(system, a, b, y, rng, N, max_draws):
    """Lines 6–14 on the whole rectangle of draws (every run evaluated on the round's largest budget,
    then masked): the form `sampled._sampled_step` replaced, kept as its reference."""
    from setsmooth.filters.sampled import _BLOCK, _PILOT, _budget

    runs = a.size
    need, drawn, got = np.full(runs, N, dtype=np.int64), np.zeros(runs, np.int64), np.zeros(runs, np.int64)
    lo, hi = np.full(runs, np.inf), np.full(runs, -np.inf)
    w_lo, w_hi = system.w_range
    active = np.arange(runs)
    while active.size:
        budget = _budget(need[active], drawn[active], got[active], max_draws)
        M = int(budget.max())
        if active.size * M > _BLOCK:
            M = max(_PILOT, _BLOCK // active.size)
            budget = np.minimum(budget, M)
        x_prev = rng.random((active.size, M)) * (b[active] - a[active])[:, None] + a[active][:, None]
        w = rng.random((active.size, M)) * (w_hi - w_lo) + w_lo
        x = system.eta(x_prev) + w
        v_lo, v_hi = system.conditional_v(w)
        yk = y[active][:, None]
        ok = (system.measurement(x, v_lo) <= yk) != (system.measurement(x, v_hi) < yk)
        ok &= np.arange(M)[None, :] < budget[:, None]
        total, used = ok.sum(axis=1), budget.copy()
        for r in np.flatnonzero(total > need[active]):
            count = np.cumsum(ok[r])
            ok[r] &= count <= need[active[r]]
            used[r] = np.argmax(count >= need[active[r]]) + 1
            total[r] = need[active[r]]
        lo[active] = np.minimum(lo[active], np.where(ok, x, np.inf).min(axis=1))
        hi[active] = np.maximum(hi[active], np.where(ok, x, -np.inf).max(axis=1))
        drawn[active] += used
        got[active] += total
        need[active] -= total
        active = active[(need[active] > 0) & (drawn[active] < max_draws)]
    return lo, hi, got, drawn


@pytest.mark.parametrize("N, max_draws", [(300, 10**6), (5000, 10**6), (800, 2500)])
def test_a_step_evaluated_on_the_counted_candidates_equals_the_rectangular_step(N, max_draws):
    # Runs of very different acceptance rates (wide and narrow priors), so budgets differ per round,
    # some runs overshoot their need and, with the small cap, some stop at max_draws.
    from setsmooth.filters.sampled import _sampled_step

    rng = np.random.default_rng(11)
    a = rng.uniform(0.0, 0.5, 40)
    b = a + np.geomspace(1e-3, 1.0, 40)
    y = eta_27(rng.uniform(a, b)) + 0.5
    ours = _sampled_step(SYSTEM, a, b, y, np.random.default_rng(5), N, max_draws)
    reference = _rectangular_step(SYSTEM, a, b, y, np.random.default_rng(5), N, max_draws)
    for mine, ref in zip(ours[:2], reference[:2]):
        finite = np.isfinite(ref)
        assert np.array_equal(mine[finite], ref[finite]) and np.all(np.isnan(mine[~finite]))
    assert np.array_equal(ours[2], reference[2]) and np.array_equal(ours[3], reference[3])
    assert (ours[2] == N).any() and (ours[2] < N).any() or max_draws > 10**5
