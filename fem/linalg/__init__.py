"""Linear algebra: one place that chooses and runs the sparse solver.

Direct factorizations (SuperLU, PARDISO, UMFPACK) with row/column scaling and
iterative refinement, the memory check that refuses a factorization that cannot fit,
the `Refactorizer` that keeps one sparsity analysis across Newton steps, and the
preconditioned Krylov solver for systems too large to factorize. `resolve` makes
the direct/Krylov choice from the size of the system.
"""


from ._direct import (AUTO_KRYLOV_ABOVE, AUTO_PARDISO_ABOVE, Refactorizer, available, factorize, in_core_bytes, resolve, scaled_solver, scaling)
from ._memory import MemoryLimitError, analysis_bytes, budget, resident_memory, set_memory_cap
from ._krylov import KrylovError, krylov_blocks, krylov_solver

__all__ = ["AUTO_KRYLOV_ABOVE", "AUTO_PARDISO_ABOVE", "KrylovError", "MemoryLimitError", "Refactorizer", "analysis_bytes", "available", "budget", "factorize", "in_core_bytes", "krylov_blocks", "krylov_solver", "resident_memory", "resolve", "scaled_solver", "scaling", "set_memory_cap"]
