"""`presolved.CompiledProduct` is scipy's sparse product bit for bit, and `highs._array` is
``np.array(values, dtype=float)`` bit for bit: the warm chains' checks and certificates rely on both
to leave every hull unchanged."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from setsmooth.solvers.highs import _array
from setsmooth.solvers.presolved import CompiledProduct


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def _matrix(rng, fmt: str, canonical: bool):
    """A random CSR or CSC matrix with wide-ranging entries; not canonical: each major slice's
    entries unsorted and with duplicates."""
    m, p = 40, 70
    major, minor = (m, p) if fmt == "csr" else (p, m)
    indptr = np.r_[0, np.cumsum(rng.integers(0, 12, major))]
    indices = rng.integers(0, minor, indptr[-1]).astype(np.int32)
    data = rng.standard_normal(indptr[-1]) * 10.0 ** rng.integers(-8, 8, indptr[-1])
    S = (sp.csr_matrix if fmt == "csr" else sp.csc_matrix)((data, indices, indptr), shape=(m, p))
    if canonical:
        S.sum_duplicates()
    assert S.has_canonical_format == canonical
    return S


@pytest.mark.parametrize("fmt", ["csr", "csc"])
@pytest.mark.parametrize("canonical", [True, False])
@pytest.mark.parametrize("transpose", [False, True])
@pytest.mark.parametrize("absolute", [False, True])
def test_compiled_product_is_scipys_bit_for_bit(fmt, canonical, transpose, absolute):
    rng = np.random.default_rng(7)
    S = _matrix(rng, fmt, canonical)
    ours = CompiledProduct(S.copy(), transpose=transpose, absolute=absolute)
    reference = abs(S.copy()) if absolute else S.copy()
    reference = reference.T if transpose else reference
    n = reference.shape[1]
    for X in (rng.standard_normal(n), rng.standard_normal((n, 1)), rng.standard_normal((n, 5)),
              rng.standard_normal((5, n)).T, np.zeros((n, 0))):
        assert _same(ours @ X, reference @ X)


def test_compiled_product_rejects_a_wrong_shape():
    with pytest.raises(ValueError):
        CompiledProduct(sp.eye(3, format="csr")) @ np.ones(4)


def test_array_is_numpys_bit_for_bit():
    values = [1.0, -0.0, 0.0, np.nan, np.inf, -np.inf, 5e-324, 1.7976931348623157e308, 0.1]
    assert _same(_array(values), np.array(values, dtype=float))
    assert _same(_array([]), np.array([], dtype=float))
