"""The eliminated sparse matrix of a nonlinear solve, its pattern built once.

The elimination of fem.assembly maps every full unknown to at most one eliminated
unknown with weight 1 (x_full = P y, P a 0/1 matrix with one entry per row at
most), so P^T K P is K with its rows and columns relabelled by `col` (full ->
eliminated, -1 dropped) and duplicates summed. The pattern is the union of the
constant matrix's entries and those of every element block (Yeoh, contact) that
will be added; each block entry gets, once, its position in the CSR data array.
A Newton iteration then only fills values:

    data = data_constant + bincount(position, values)

(no COO -> CSR conversion, no sparse products with P).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


def column_map(P: sp.csr_matrix) -> np.ndarray:
    """col[i]: the eliminated unknown of full unknown i, or -1 (P a 0/1 elimination)."""
    Pc = sp.csr_matrix(P)
    counts = np.diff(Pc.indptr)
    if counts.max(initial=0) > 1 or not np.all(Pc.data == 1):
        raise ValueError("pattern: the elimination is not a 0/1 relabelling")
    col = np.full(P.shape[0], -1)
    rows = np.flatnonzero(counts)
    col[rows] = Pc.indices[Pc.indptr[rows]]
    return col


class Pattern:
    """The eliminated matrix P^T (A + sum of element blocks) P for changing block values."""

    def __init__(self, P: sp.csr_matrix, A: sp.spmatrix, blocks: dict[str, tuple[np.ndarray, np.ndarray]]):
        """`blocks`: name -> (full row indices, full column indices) of the element
        entries, any shape (the values given to `matrix` have the same shape)."""
        self.col = col = column_map(P)
        self.n = n = P.shape[1]
        Ar = sp.coo_matrix(P.T @ A @ P)
        keys = [Ar.row.astype(np.int64) * n + Ar.col]
        self._keep = {}
        for name, (r, c) in blocks.items():
            rr, cc = col[np.asarray(r).ravel()], col[np.asarray(c).ravel()]
            keep = (rr >= 0) & (cc >= 0)
            self._keep[name] = (keep, rr[keep].astype(np.int64) * n + cc[keep])
            keys.append(self._keep[name][1])
        uniq = _union(np.concatenate(keys), n)
        rows, cols = uniq // n, uniq % n
        self.indptr = np.searchsorted(rows, np.arange(n + 1)).astype(np.int32)
        self.indices = cols.astype(np.int32)
        self.nnz = len(uniq)
        self.base = np.bincount(np.searchsorted(uniq, keys[0]), weights=Ar.data, minlength=self.nnz).astype(float)
        # each block entry's position in the data array; entries of dropped rows or columns
        # go to a slot past its end (no masked copy of the values at every fill)
        self.pos = {}
        for name, (keep, k) in self._keep.items():
            pos = np.full(keep.shape, self.nnz, dtype=np.intp)
            pos[keep] = np.searchsorted(uniq, k)
            self.pos[name] = pos

    def matrix(self, values: dict[str, np.ndarray]) -> sp.csr_matrix:
        """The eliminated CSR matrix with these block values added to the constant part."""
        data = np.append(self.base, 0.0)
        for name, v in values.items():
            data += np.bincount(self.pos[name], weights=np.asarray(v, dtype=float).ravel(), minlength=self.nnz + 1)
        data = data[:-1]
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))

    def reduce(self, r_full: np.ndarray) -> np.ndarray:
        """P^T r."""
        keep = self.col >= 0
        return np.bincount(self.col[keep], weights=r_full[keep], minlength=self.n)


def _union(keys: np.ndarray, n: int) -> np.ndarray:
    """The sorted distinct keys row * n + col of the entries and of their transposes (a
    structurally symmetric pattern, so a symmetric matrix is recognised as one by
    fem.linalg.Refactorizer), through scipy's COO -> CSR conversion (a counting sort by
    row, then each row's columns sorted: faster than np.unique on millions of keys)."""
    M = sp.csr_matrix((np.ones(len(keys), dtype=np.float32), (keys // n, keys % n)), shape=(n, n))
    M = (M + M.T).tocsr()            # positive counts: no entry cancels
    M.sort_indices()
    return np.repeat(np.arange(n, dtype=np.int64), np.diff(M.indptr)) * n + M.indices
