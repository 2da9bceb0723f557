"""Extended constrained zonotopes Z(G, c, A, b, h) with factor bounds h ∈ [0, ∞].

    Z(G, c, A, b, h) = { Gξ + c : Aξ = b, ξ_j ∈ [−h_j, h_j] }

(stability paper Definition 7, smoothing paper Definition 2). An infinite bound makes a factor free, so
ℝⁿ, strips, subspaces and half-spaces through the intersection with a CZ all stay CZs, and the filters'
prediction (stability (20)) and update (stability (21)) and the smoother's step (smoothing (24)) are
exact, closed-form operations on the five matrices.

Closed forms here: linear map (smoothing (35)), translation, Minkowski sum (smoothing (36)),
generalized intersection (smoothing (37)), Cartesian product, projection; the support function in
closed form when there are no constraints (nc = 0); otherwise the sparse LP of `solvers.CZProgram`.
``G`` and ``A`` may be scipy sparse matrices; operations keep them sparse.
"""

from __future__ import annotations

from functools import cached_property
from typing import Any

import cvxpy as cp
import numpy as np
import scipy.sparse as sp

from .._validation import as_matrix, as_vector, real_array
from ..solvers import CZProgram, FactorConstraints, SolverError, SupportSolution
from ..solvers.certify import _exactly_cancelled
from . import _matrices as mx
from . import rounding
from .base import ConvexSet


class ConstrainedZonotope(ConvexSet):
    """Extended constrained zonotope Z(G, c, A, b, h).

    Parameters
    ----------
    G : array_like or sparse matrix, shape (n, ng)
        Generator matrix.
    c : array_like, shape (n,)
        Centre.
    A : array_like or sparse matrix, shape (nc, ng), optional
        Constraint matrix (none by default).
    b : array_like, shape (nc,), optional
        Constraint right-hand side.
    h : array_like, shape (ng,), optional
        Factor bounds in [0, inf]; all ones by default (the classical CZ).

    Raises
    ------
    ValueError
        On shape mismatches, NaN or inf entries in G, c, A, b, or negative/NaN bounds h.

    Examples
    --------
    >>> import numpy as np, setsmooth as ss
    >>> Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[1.0])
    >>> round(Z.support([1.0, 1.0]), 6)
    1.0
    """

    #: See `_init`; a class default for subclasses that do not call it (`PosteriorView`).
    _reference = None

    def __init__(self, G: Any, c: Any, A: Any = None, b: Any = None, h: Any = None):
        G = as_matrix(G, "G", allow_sparse=True)
        n, ng = G.shape
        c = as_vector(c, "c", n)
        if A is None and b is None:
            A, b = np.zeros((0, ng)), np.zeros(0)
        elif A is None or b is None:
            raise ValueError("A and b must be given together")
        else:
            A = as_matrix(A, "A", cols=ng, allow_sparse=True)
            b = as_vector(b, "b", A.shape[0])
        if h is None:
            h = np.ones(ng)
        else:
            h = real_array(h, "h")
            h = h.reshape(-1) if h.ndim else np.full(ng, float(h))
            if h.shape != (ng,):
                raise ValueError(f"h must have length ng = {ng}, got shape {h.shape}")
            if np.isnan(h).any() or (h < 0).any():
                raise ValueError("h must lie in [0, inf] (no NaN, no negative bounds)")
        self._init(G, c, A, b, h, None)

    def _init(self, G, c, A, b, h, factors: FactorConstraints | None,
              pad: np.ndarray | None = None, slack: np.ndarray | None = None,
              pad_free: np.ndarray | None = None, slack_free: np.ndarray | None = None,
              pad_generators: np.ndarray | None = None) -> None:
        self.G = G if sp.issparse(G) else mx.readonly(G)
        self.c = mx.readonly(c)
        self.A = A if sp.issparse(A) else mx.readonly(A)
        self.b = mx.readonly(b)
        self.h = mx.readonly(h)
        self.dim = self.G.shape[0]
        if factors is not None and slack is None and slack_free is None:
            slack, slack_free = factors.slack, factors.slack_free
        self._factors = factors
        # The algebra's own rounding (`setsmooth.sets.rounding`): None where nothing was rounded.
        # A point of the exact set is within box(pad) ⊕ Z(pad_generators) ⊕ box(pad_free·‖ξ_F‖∞)
        # of c + Gξ, for ξ with |Aξ − b| ≤ slack + slack_free·‖ξ_F‖∞ (ξ_F: the free factors).
        # Linear maps carry the pad generators exactly (`rounding.mapped_pad`); ``pad`` is the box
        # hull of both parts, what code that reads a CZ's data sees.
        self._pad_box = None if pad is None else mx.readonly(pad)
        self._pad_generators = None if pad_generators is None else mx.readonly(pad_generators)
        hull = rounding.pad_hull(pad, pad_generators)
        self.pad = None if hull is None else mx.readonly(hull)
        self.pad_free = None if pad_free is None else mx.readonly(pad_free)
        self._slack = None if slack is None else mx.readonly(slack)
        self._slack_free = None if slack_free is None else mx.readonly(slack_free)
        #: A `setsmooth.trajectories.recursion_certificates.DataReference` (the same exact set,
        #: posed on the model data) on the sets of the recursion's estimators, which answers their
        #: supports, hulls, emptiness and membership; None otherwise.
        self._reference = None

    def _with_reference(self, reference) -> "ConstrainedZonotope":
        """This CZ with its queries answered by ``reference.get()`` (internal)."""
        out = ConstrainedZonotope._trusted(self.G, self.c, self.A, self.b, self.h, self._factors,
                                           self._pad_box, self._slack, self.pad_free, self._slack_free,
                                           self._pad_generators)
        out._reference = reference
        return out

    @property
    def slack(self) -> np.ndarray | None:
        """Rounding slack of the constraint rows (`setsmooth.sets.rounding`), None when exact."""
        return self._slack

    @property
    def slack_free(self) -> np.ndarray | None:
        """The rows' rounding slack per unit of ‖ξ_F‖∞ (rounded free columns), None when exact."""
        return self._slack_free

    @classmethod
    def _trusted(cls, G, c, A, b, h, factors: FactorConstraints | None = None,
                 pad: np.ndarray | None = None, slack: np.ndarray | None = None,
                 pad_free: np.ndarray | None = None, slack_free: np.ndarray | None = None,
                 pad_generators: np.ndarray | None = None) -> "ConstrainedZonotope":
        """Build without validation (internal: operands already validated)."""
        obj = cls.__new__(ConstrainedZonotope)
        obj._init(G, c, A, b, h, factors, pad, slack, pad_free, slack_free, pad_generators)
        return obj

    def materialized(self) -> "ConstrainedZonotope":
        """The same enclosure with the rounding charges written as generators (pad and slack zero).

        ``pad`` becomes a box generator per padded coordinate, ``slack`` a column diag(slack) in A
        (with a zero generator), each with bound 1: the result, as stored, contains every point this
        CZ's charges cover. For code that reads G, c, A, b, h directly (order reductions, programs
        built from a CZ's data).
        """
        if not self._charged:
            return self
        pad, slack = self.pad, self._slack
        if self.pad_free is not None or self._slack_free is not None:
            beta = self.factors.free_bound()
            if beta is None:
                raise ValueError("this CZ's free factors have rounded columns and no known bound: "
                                 "its rounding cannot be written as bounded generators")
            pad = rounding.add(pad, None if self.pad_free is None else self.pad_free * beta)
            slack = rounding.add(slack, None if self._slack_free is None else self._slack_free * beta)
        G, A, h = self.G, self.A, self.h
        sparse = mx.any_sparse(G, A)
        # New factors of bound 1: the slack's columns in A (zero in G), the pad's in G (zero in A).
        for charge, in_A in ((slack, True), (pad, False)):
            if charge is None:
                continue
            rows = np.flatnonzero(charge)
            shape = (self.nc if in_A else self.dim, rows.size)
            if sparse:
                D = sp.csc_matrix((charge[rows], (rows, np.arange(rows.size))), shape=shape)
            else:  # written directly: a CSC matrix built only to be densified was 7 % of an LSU-CZ profile
                D = np.zeros(shape)
                D[rows, np.arange(rows.size)] = charge[rows]
            zeros = mx.zeros_like_kind(self.dim if in_A else self.nc, rows.size, sparse)
            A = mx.hstack([A, D if in_A else zeros])
            G = mx.hstack([G, zeros if in_A else D])
            h = np.concatenate([h, np.ones(rows.size)])
        return ConstrainedZonotope._trusted(G, self.c, A, self.b, h)

    # -- sizes -----------------------------------------------------------------------------------------
    @property
    def ng(self) -> int:
        """Number of generators (factors)."""
        return self.G.shape[1]

    @property
    def nc(self) -> int:
        """Number of equality constraints."""
        return self.A.shape[0]

    def __repr__(self) -> str:
        return f"ConstrainedZonotope(dim={self.dim}, ng={self.ng}, nc={self.nc})"

    # -- CVXPY membership (the generic path) -----------------------------------------------------------
    def constraints(self, x: cp.Expression) -> list[cp.Constraint]:
        # Stated in normalized factors ξ = s∘η (s = h on bounded factors, so |η| ≤ 1; the inverse
        # column size on free ones) and unit-size constraint rows: the same set written with rows
        # or factors scaled by 1e±12 then compiles to the same program, where the raw form left
        # rows of size 1e-12 to the solver's absolute accuracy (42 of 60 rescaled CZs were wrong).
        G, A, b, h = self.G, self.A, self.b, self.h
        finite = np.isfinite(h)
        size = np.maximum(_column_max(G), _column_max(A))
        s = np.where(finite, h, 1.0 / np.where(size > 0, size, 1.0))
        G, A = _scale_columns(G, s), _scale_columns(A, s)
        row = _column_max(A.T)
        keep = row > 0  # a zero row is 0 = b: kept as is (inconsistent when b ≠ 0)
        r = np.where(keep, 1.0 / np.where(keep, row, 1.0), 1.0)
        # Coordinates too: row i of x = Gη + c divided by its largest term.
        rho = np.maximum(_column_max(G.T), np.abs(self.c))
        rho = np.where(rho > 0, rho, 1.0)
        eta = cp.Variable(self.ng)
        cons = [cp.multiply(1.0 / rho, x) == _scale_columns(G.T, 1.0 / rho).T @ eta + self.c / rho]
        if self.nc:
            cons.append(_scale_columns(A.T, r).T @ eta == r * b)
        if finite.any():
            cons.append(cp.abs(eta[np.flatnonzero(finite)]) <= 1.0)
        return cons

    # -- fast path -------------------------------------------------------------------------------------
    @property
    def factors(self) -> FactorConstraints:
        """The factor set {ξ : Aξ = b, |ξ| ≤ h}, shared with every map and projection of this CZ."""
        if self._factors is None:
            self._factors = FactorConstraints(self.A, self.b, self.h, self._slack, self._slack_free)
        return self._factors

    @cached_property
    def _program(self) -> CZProgram:
        return CZProgram(self.G, self.c, self.factors, self.pad, self.pad_free)

    def _as_constrained_zonotope(self) -> "ConstrainedZonotope":
        return self

    def _support(self, D: np.ndarray, certified: bool):
        if self._reference is not None:
            return self._reference.get()._support(D, certified)
        if self.nc == 0:
            values, points = self._unconstrained_support(D)
            if certified is not False:
                values = self._certified_closed_form(D, values)
            return values, points
        values, points = self._program.support(D, certified)
        if certified is not False and self._charged and np.isneginf(values).any():
            # The stored set is empty; the exact one may hold points within the rows' slack.
            try:
                relaxed = self.materialized()
            except ValueError:
                if certified is True:
                    raise SolverError("UncertifiableReducedCost",
                                      "certifying the support of a set stored empty: its exact rows "
                                      "may be consistent within their rounding slack, which is "
                                      "charged on free factors of unknown bound", kind="support")
                return values, points
            return relaxed._support(D, certified)
        return values, points

    def _certified_closed_form(self, D: np.ndarray, values: np.ndarray) -> np.ndarray:
        """Upper bounds on the closed-form support values dᵀc + Σ_j h_j |(Gᵀd)_j| (no constraints):
        their rounding (γ over the n + ng products and sums, η for each product that may have
        underflowed, times h_j) and the pad, charged. A free factor makes the exact value +∞
        unless its (Gᵀd)_j is exactly zero (checked in rationals where the computed one is zero but
        not its rounding bound) and no rounded free column (``pad_free``) is seen."""
        n = self.dim
        absG = abs(self.G) if sp.issparse(self.G) else np.abs(self.G)
        finite = np.isfinite(self.h)
        hf = np.where(finite, self.h, 0.0)
        reach = np.asarray((absG.T @ np.abs(D).T).T)  # (k, ng): Σ_i |G_ij d_i|
        magnitude = np.abs(D) @ np.abs(self.c) + reach @ hf
        out = rounding.upper_bound(values, magnitude, n + self.ng + 1, absolute=n * (1.0 + hf.sum()))
        if self.pad is not None:
            with np.errstate(invalid="ignore"):
                out = np.nextafter(out + rounding.rounded_up(rounding.abs_matvec(D, self.pad), n),
                                   np.inf)
        if not finite.all():
            free = np.flatnonzero(~finite)
            for i in np.flatnonzero(np.isfinite(out)):
                unsure = reach[i, free] > 0  # the computed (Gᵀd)_j = 0 there (else out is ∞)
                seen_free_pad = (self.pad_free is not None
                                 and rounding.abs_matvec(D[i], self.pad_free) > 0)
                if seen_free_pad or (unsure.any() and not _exactly_cancelled(
                        D[i:i + 1], self.G, sp.csc_matrix((0, self.ng)), np.zeros((1, 0)),
                        free[unsure])):
                    out[i] = np.inf
        return out

    def _interval_hulls_at_once(self) -> dict | None:
        # The plain hull's solves also certify it (`CZProgram.support_and_bounds`): computing one
        # keeps the other, half the LPs where both are asked for (the reliability comparisons).
        if self._reference is not None:
            return self._reference.get()._interval_hulls_at_once()
        if self.nc == 0:
            return None  # closed form
        eye = np.eye(self.dim)
        values, bounds = self._program.support_and_bounds(np.vstack([eye, -eye]))
        if self._charged and bounds is not None and np.isneginf(bounds).any():
            # stored empty: the certified hulls are the relaxed set's (`_support`)
            return {False: self._box_of_supports(values, self.dim)}
        return self._hulls_of_supports(values, bounds)

    def _hulls_of_supports(self, values: np.ndarray, bounds: np.ndarray | None) -> dict:
        """The interval hulls, by ``certified`` flag, of one set of solves along [I; −I]: the
        solver's ``values`` (False) and their certified ``bounds`` (True, and the default None),
        or the values for None where no sound bound exists (``bounds`` None)."""
        hulls = {False: self._box_of_supports(values, self.dim)}
        if bounds is None:
            hulls[None] = hulls[False]
        else:
            hulls[None] = hulls[True] = self._box_of_supports(bounds, self.dim)
        return hulls

    def support_solution(self, d: Any) -> SupportSolution:
        """The support value of direction ``d`` with its maximizer, factor vector and multipliers.

        Parameters
        ----------
        d : array_like, shape (dim,)

        Returns
        -------
        SupportSolution
            ``value`` = h_Z(d), ``point`` = Gξ + c attaining it, ``factors`` = ξ (with Aξ = b,
            |ξ| ≤ h), ``multipliers`` = λ of Aξ = b (shape (nc,); the dual solution of the fast
            path's LP, for the original rows). NaN arrays where the value is infinite.

        Examples
        --------
        >>> import numpy as np, setsmooth as ss
        >>> Z = ss.ConstrainedZonotope(np.eye(2), np.zeros(2), A=[[1.0, 1.0]], b=[1.0])
        >>> sol = Z.support_solution([1.0, 0.0])
        >>> round(sol.value, 6), (np.round(sol.factors, 6) + 0.0).tolist()   # + 0.0: no −0.0
        (1.0, [1.0, 0.0])
        """
        d = as_vector(d, "d", self.dim)
        if self.nc == 0:
            values, points = self._unconstrained_support(d[None, :])
            g = np.asarray(self.G.T @ d).reshape(-1)
            with np.errstate(invalid="ignore"):
                xi = np.where(g == 0.0, 0.0, np.sign(g) * self.h)
            if not np.isfinite(values[0]):
                xi = np.full(self.ng, np.nan)
            return SupportSolution(float(values[0]), points[0], xi, np.zeros(0))
        return self._program.solutions(d[None, :])[0]

    def _unconstrained_support(self, D: np.ndarray):
        # h_Z(d) = dᵀc + Σ_j h_j |(Gᵀd)_j|, with 0·∞ = 0 for factors the direction does not see.
        g = np.asarray((self.G.T @ D.T).T)
        with np.errstate(invalid="ignore"):
            weight = np.where(g == 0.0, 0.0, np.abs(g) * self.h)
            xi = np.where(g == 0.0, 0.0, np.sign(g) * self.h)
            values = D @ self.c + weight.sum(axis=1)
            points = np.asarray((self.G @ xi.T).T) + self.c
        points[~np.isfinite(values)] = np.nan
        return values, points

    @property
    def _charged(self) -> bool:
        """Whether this CZ carries rounding charges (`setsmooth.sets.rounding`)."""
        return not (self.pad is None and self._slack is None and self.pad_free is None
                    and self._slack_free is None)

    def _is_empty(self) -> bool:
        if self._reference is not None:
            return self._reference.get().is_empty()
        if not self.factors.is_empty():
            return False
        # The stored rows are inconsistent; the exact ones may not be, within their slack: the
        # verdict is the materialized set's (slack written as generators) where there are charges.
        if self._charged:
            try:
                return self.materialized().factors.is_empty()
            except ValueError:  # free charges without a known bound: emptiness not shown
                return False
        return True

    def _contains(self, p: np.ndarray, margin) -> bool:
        # The distance program in normalized coordinates (x − p)/s, where the set and the margin
        # have unit size or less, so that the program's accuracy (SOLVER_TOL, with an absolute floor
        # at 1) is relative to the set. Per-coordinate margins: s = margin / MEMBERSHIP_TOL
        # (`sets.membership`); a scalar margin: one s for all coordinates, the largest of the
        # margin, the generators' reach and the distance of the centre. The factor set and its
        # presolve are shared.
        from .membership import normalization

        if self._reference is not None:
            return self._reference.get()._contains(p, margin)
        if np.ndim(margin) == 0:
            hf = np.where(np.isfinite(self.h), self.h, 0.0)
            reach = np.asarray(abs(self.G) @ hf).ravel()  # Σ_j |G_ij| h_j over bounded factors
            sigma = max(float(margin), float(np.abs(self.c - p).max(initial=0.0)),
                        float(reach.max(initial=0.0)))
            if not np.isfinite(sigma) or sigma == 0.0:
                return self._program.contains(p, float(margin))
            return self._contains_normalized(p, np.full(self.dim, sigma), float(margin) / sigma)
        s, _ = normalization(p, margin)
        return self._contains_normalized(p, s, float(np.max(margin / s)))

    def _contains_normalized(self, p: np.ndarray, s: np.ndarray, margin: float) -> bool:
        """Whether a member lies within ∞-distance ``margin`` of p in the coordinates (x − p)/s."""
        if self._reference is not None:
            return self._reference.get()._contains_normalized(p, s, margin)
        G = sp.diags(1.0 / s) @ self.G if sp.issparse(self.G) else self.G / s[:, None]
        scaled = ConstrainedZonotope._trusted(G, (self.c - p) / s, self.A, self.b, self.h,
                                              self.factors)
        return scaled._program.contains(np.zeros(self.dim), margin)

    def chebyshev_ball(self):
        """The largest Euclidean ball inside the CZ (`setsmooth.sets.chebyshev.chebyshev_ball`).

        Exact in dimensions 1 and 2 and for zonotopes with few facets; otherwise a ball inside
        the set from one SOCP, with ``exact`` True only when it provably is the largest.

        Returns
        -------
        ChebyshevBall
            ``center``, ``radius``, ``exact``.

        Examples
        --------
        >>> import numpy as np, setsmooth as ss
        >>> ball = ss.ConstrainedZonotope(np.diag([2.0, 1.0]), np.zeros(2)).chebyshev_ball()
        >>> (np.round(ball.center, 6) + 0.0).tolist(), round(ball.radius, 6), ball.exact   # + 0.0: no -0.0
        ([0.0, 0.0], 1.0, True)
        """
        from .chebyshev import chebyshev_ball

        return chebyshev_ball(self)

    # -- closed-form algebra ---------------------------------------------------------------------------
    def _linear_map(self, M) -> "ConstrainedZonotope":
        """M Z = Z(MG, Mc, A, b, h) (smoothing paper (35), stability (11)), its rounding charged;
        the earlier charges are carried as pad generators (`rounding.mapped_pad`), not wrapped."""
        fresh, pad_free = rounding.linear_image(M, self.G, self.c, self.h, None, self.pad_free)
        generators, carried = rounding.mapped_pad(M, self._pad_box, self._pad_generators)
        return ConstrainedZonotope._trusted(mx.matmul(M, self.G), np.asarray(M @ self.c).reshape(-1),
                                            self.A, self.b, self.h, self._factors,
                                            rounding.add(fresh, carried), self._slack,
                                            pad_free, self._slack_free, generators)

    def _translate(self, v: np.ndarray) -> "ConstrainedZonotope":
        c, err = rounding.sum_with_error(self.c, v)
        return ConstrainedZonotope._trusted(self.G, c, self.A, self.b, self.h, self._factors,
                                            rounding.add(self._pad_box, err if err.any() else None),
                                            self._slack, self.pad_free, self._slack_free,
                                            self._pad_generators)

    # The algebra hooks are these two exact CZ operations.
    def _closed_linear_map(self, M) -> "ConstrainedZonotope":
        return self._linear_map(M)

    def _closed_translate(self, v: np.ndarray) -> "ConstrainedZonotope":
        return self._translate(v)

    def _project(self, idx: np.ndarray) -> "ConstrainedZonotope":
        G = self.G[idx] if not sp.issparse(self.G) else sp.csc_matrix(self.G.tocsr()[idx])
        return ConstrainedZonotope._trusted(G, self.c[idx], self.A, self.b, self.h, self._factors,
                                            None if self._pad_box is None else self._pad_box[idx],
                                            self._slack,
                                            None if self.pad_free is None else self.pad_free[idx],
                                            self._slack_free, _selected_rows(self._pad_generators, idx))

    def _minkowski_sum(self, other: "ConstrainedZonotope") -> "ConstrainedZonotope":
        """Z ⊕ W (smoothing paper (36)); the rounding of c_Z + c_W charged to the pad."""
        A, b, h = mx.block_diag(self.A, other.A), np.concatenate([self.b, other.b]), \
            np.concatenate([self.h, other.h])
        c, err = rounding.sum_with_error(self.c, other.c)
        pad = rounding.add(self._pad_box, other._pad_box, err if err.any() else None)
        slack, slack_free = _stacked_slack((self, other))
        return ConstrainedZonotope._trusted(mx.hstack([self.G, other.G]), c, A, b, h,
                                            _joined_factors(A, b, h, slack, slack_free, self, other),
                                            pad, slack, rounding.add(self.pad_free, other.pad_free),
                                            slack_free, _side_by_side(self._pad_generators,
                                                                      other._pad_generators))

    def _cartesian_product(self, other: "ConstrainedZonotope") -> "ConstrainedZonotope":
        A, b, h = mx.block_diag(self.A, other.A), np.concatenate([self.b, other.b]), \
            np.concatenate([self.h, other.h])
        slack, slack_free = _stacked_slack((self, other))
        return ConstrainedZonotope._trusted(
            mx.block_diag(self.G, other.G), np.concatenate([self.c, other.c]), A, b, h,
            _joined_factors(A, b, h, slack, slack_free, self, other),
            _stacked((self._pad_box, other._pad_box), (self.dim, other.dim)), slack,
            _stacked((self.pad_free, other.pad_free), (self.dim, other.dim)), slack_free,
            _block_diagonal(self._pad_generators, other._pad_generators, self.dim, other.dim))

    def _generalized_intersection(self, R, Y: "ConstrainedZonotope") -> "ConstrainedZonotope":
        """Z ∩_R Y = {z ∈ Z : Rz ∈ Y} (smoothing paper (37); stability (21) with R = C).

        G = [G_z 0], c = c_z, A = [[A_z, 0], [0, A_y], [R G_z, −G_y]], b = [b_z; b_y; c_y − R c_z],
        h = [h_z; h_y]. The new rows' slack charges what they lost (`setsmooth.sets.rounding`): for
        z = c_z + G_zξ + e_z and Rz = c_y + G_yη + e_y exactly, the stored row fl(R G_z)ξ − G_yη − b_new
        equals (fl(R G_z) − R G_z)ξ + (c_y − R c_z − b_new) + e_y − R e_z, bounded by
        Σ_j h_j |error of (R G_z)_j| + |error of b_new| + pad_y + |R| pad_z.
        """
        sparse = mx.any_sparse(self.G, self.A, Y.G, Y.A, R)
        RG = mx.matmul(R, self.G)
        A = mx.vstack([
            mx.block_diag(self.A, Y.A),
            mx.hstack([RG, -Y.G]),
        ])
        if sparse and not sp.issparse(A):
            A = sp.csc_matrix(A)
        G = mx.hstack([self.G, mx.zeros_like_kind(self.dim, Y.ng, sp.issparse(self.G))])
        Rc = np.asarray(R @ self.c).reshape(-1)
        b_new, err_b = rounding.sum_with_error(Y.c, -Rc)
        # |fl(R c_z) − R c_z| and |fl(R G_z) − R G_z|·h are `linear_image`'s pad of R·Z (with R's
        # image of Z's pad); the subtraction's exact error and Y's pad complete the row's charge.
        image, image_free = rounding.linear_image(R, self.G, self.c, self.h, self.pad, self.pad_free)
        new_rows = rounding.add(image, err_b if err_b.any() else None, Y.pad)
        new_rows_free = rounding.add(image_free, Y.pad_free)
        b = np.concatenate([self.b, Y.b, b_new])
        h = np.concatenate([self.h, Y.h])
        slack, slack_free = _stacked_slack((self, Y), (new_rows, new_rows_free), R.shape[0])
        return ConstrainedZonotope._trusted(G, self.c, A, b, h,
                                            _joined_factors(A, b, h, slack, slack_free, self, Y),
                                            self._pad_box, slack, self.pad_free, slack_free,
                                            self._pad_generators)


def _selected_rows(P: np.ndarray | None, idx: np.ndarray) -> np.ndarray | None:
    """Rows ``idx`` of pad generators (None stays None)."""
    return None if P is None else P[idx]


def _side_by_side(P: np.ndarray | None, Q: np.ndarray | None) -> np.ndarray | None:
    """The pad generators of a Minkowski sum: both sets' columns (None meaning none)."""
    if P is None or Q is None:
        return Q if P is None else P
    return np.hstack([P, Q])


def _block_diagonal(P: np.ndarray | None, Q: np.ndarray | None, n: int, m: int) -> np.ndarray | None:
    """The pad generators of a Cartesian product (None meaning none)."""
    if P is None and Q is None:
        return None
    P = np.zeros((n, 0)) if P is None else P
    Q = np.zeros((m, 0)) if Q is None else Q
    out = np.zeros((n + m, P.shape[1] + Q.shape[1]))
    out[:n, :P.shape[1]], out[n:, P.shape[1]:] = P, Q
    return out


def _stacked(parts, sizes) -> np.ndarray | None:
    """Vectors one below the other (None meaning zeros of its size); None if all are None."""
    if all(p is None for p in parts):
        return None
    return np.concatenate([np.zeros(k) if p is None else p for p, k in zip(parts, sizes)])


def _stacked_slack(operands, extra=(None, None), n_extra: int = 0):
    """(slack, slack_free): the operands' row charges one below the other, then ``extra``'s for
    ``n_extra`` new rows."""
    sizes = [Z.nc for Z in operands] + [n_extra]
    return (_stacked([Z.slack for Z in operands] + [extra[0]], sizes),
            _stacked([Z.slack_free for Z in operands] + [extra[1]], sizes))


def _joined_factors(A, b, h, slack, slack_free,
                    *operands: "ConstrainedZonotope") -> FactorConstraints | None:
    """The factor set of a CZ built from ``operands``' factors side by side (None: built lazily).

    Only when an operand has free factors: their known bounds carry over (`FactorConstraints.joined`).
    """
    if all(np.isfinite(Z.h).all() for Z in operands):
        return None
    return FactorConstraints.joined(A, b, h, [Z.factors for Z in operands], slack, slack_free)


def _column_max(M) -> np.ndarray:
    """Largest absolute entry of every column of a dense or sparse matrix (0 for an empty one)."""
    if M.shape[0] == 0:
        return np.zeros(M.shape[1])
    if sp.issparse(M):
        return np.asarray(abs(M).max(axis=0).todense()).ravel()
    return np.abs(M).max(axis=0)


def _scale_columns(M, s: np.ndarray):
    return sp.csc_matrix(M @ sp.diags(s)) if sp.issparse(M) else M * s


def empty_constrained_zonotope(n: int) -> ConstrainedZonotope:
    """A CZ with the contradictory constraint 0·ξ = 1: the empty set of ℝⁿ as a CZ."""
    return ConstrainedZonotope._trusted(np.zeros((n, 1)), np.zeros(n), np.zeros((1, 1)),
                                        np.ones(1), np.ones(1))
