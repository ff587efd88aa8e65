"""PARDISO in core against out of core (fem.linalg.check_fits) on one matrix, side by side:
the solve's wall time per number of right-hand sides and, out of core, how many times the
solve reads the factors from disk (this process's read bytes, /proc/self/io rchar, over the
factors' size, MKL iparm 17). Why the 16x16 array of benchmarks/array_8x8.py spends its time
in the solves: a symmetry class has up to 65 right-hand sides.

The matrix: the 7-point 3D Laplacian on an n^3 grid (n = 30: 27 000 unknowns), symmetric
positive definite like the reduced coupled system's shape (PARDISO mtype -2 as fem.linalg
passes it); out of core is forced by a budget of 0.8 x what the in-core factors need.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/out_of_core_solve.py [n]
"""

from __future__ import annotations

import sys
import time

import numpy as np
import pypardiso
import scipy.sparse as sp
from pyamg.gallery import poisson

from taxel.fem import linalg


def read_bytes() -> int:
    with open("/proc/self/io") as fh:
        return int(next(line for line in fh if line.startswith("rchar")).split()[1])


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 30
    A = poisson((n, n, n), format="csr")
    probe = pypardiso.PyPardisoSolver(mtype=-2)
    need = linalg.analysis_bytes(probe, sp.csr_matrix(sp.triu(A)))
    factors = 1024.0 * probe.get_iparm(17)           # (the factors alone, besides the need)
    probe.free_memory(True)
    in_core = linalg.factorize(A, "pardiso")
    linalg.set_memory_cap(linalg.resident_memory() + 0.8 * need)    # the budget: 80 % of the need
    out_of_core = linalg.factorize(A, "pardiso")
    linalg.set_memory_cap(None)
    print(f"{A.shape[0]} unknowns, factors {factors / 1e6:.0f} MB")
    print("right-hand sides | in core s | out of core s | ratio | out-of-core reads of the factors")
    rng = np.random.default_rng(0)
    for k in (1, 4, 16, 64):
        B = rng.random((A.shape[0], k))
        t0 = time.perf_counter()
        X0 = in_core(B)
        t1 = time.perf_counter()
        r0 = read_bytes()
        X1 = out_of_core(B)
        t2 = time.perf_counter()
        reads = (read_bytes() - r0) / factors
        assert np.allclose(X0, X1, rtol=0, atol=1e-10 * np.abs(X0).max())
        print(f"{k:>16} | {t1 - t0:9.3f} | {t2 - t1:13.3f} | {(t2 - t1) / (t1 - t0):5.1f} | {reads:.1f}")


if __name__ == "__main__":
    main()
