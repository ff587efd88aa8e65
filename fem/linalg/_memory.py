"""The memory check of a direct factorization: the budget (the free memory, or a cap
this process is given), PARDISO's analysis of what the factors need, out-of-core
factorization when they do not fit in memory, and the refusal (`MemoryLimitError`,
one line with the fix) when they fit nowhere, before the factorization starts.
"""

from __future__ import annotations

import ctypes
import logging
import os
import shutil
import tempfile
import weakref

import numpy as np

log = logging.getLogger(__name__)

# The memory this process may use in all (bytes; None: whatever is free). A caller on a shared
# machine sets it (benchmarks/array_8x8.py --cap-gb); a factorization that would not fit
# in it in core goes out of core (check_fits).
MEMORY_CAP: float | None = None


def set_memory_cap(cap: float | None) -> None:
    """Bytes this process may hold in all (None: no cap beyond the free memory); a
    factorization that would not fit under it runs out of core (`check_fits`)."""
    global MEMORY_CAP
    MEMORY_CAP = cap


FIX = "coarsen mesh.size / mesh.piezo_size, use fewer elements through the piezo, or model less (2D, axisymmetric)"


class MemoryLimitError(ValueError):
    """A factorization that cannot fit in this machine's free memory (found by
    PARDISO's symbolic analysis, before the numerical factorization starts)."""


def available_memory() -> float:
    """Free memory for a new allocation (MemAvailable of /proc/meminfo), bytes."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES"))


def resident_memory() -> float:
    """This process's resident memory, bytes."""
    with open("/proc/self/statm") as fh:
        return float(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def budget() -> float:
    """Bytes a new factorization may use: the free memory, and under MEMORY_CAP no more
    than the cap less what this process already holds."""
    have = available_memory()
    return have if MEMORY_CAP is None else min(have, MEMORY_CAP - resident_memory())


def analysis_bytes(solver, A) -> float:
    """PARDISO's analysis (phase 11); the bytes its factorization needs in core
    (iparm 15: the analysis's peak, 16 + 17: permanent + factors, in KB)."""
    solver.set_phase(11)
    solver._call_pardiso(A, np.zeros((A.shape[0], 1)))
    return 1024.0 * max(solver.get_iparm(15), solver.get_iparm(16) + solver.get_iparm(17))


def check_fits(solver, A) -> None:
    """PARDISO's analysis phase (11) reports the memory the factorization will need;
    when that exceeds the budget (the free memory, or MEMORY_CAP) the factorization goes
    out of core: MKL's defaults for the matrix type (pardisoinit), iparm[59] = 2, the
    factors in files in a temporary folder of its own (MKL_PARDISO_OOC_PATH; under
    $TMPDIR, removed with the solver: never the working directory, which is the user's)
    and at most MKL_PARDISO_OOC_MAX_CORE_SIZE of them in memory (set to 0.6 x the
    budget), the analysis redone. Refused (MemoryLimitError) before factorizing when
    even that does not fit, in memory or on that folder's disk, instead of being killed
    by the kernel halfway."""
    need, have = analysis_bytes(solver, A), budget()
    log.info("PARDISO analysis: %d unknowns, %.3g GB in core, %.3g GB free", A.shape[0], need / 1e9, have / 1e9)
    if need <= 0.9 * have:
        return
    solver.free_memory(True)
    solver.libmkl.pardisoinit(solver.pt.ctypes.data_as(ctypes.c_void_p), ctypes.byref(ctypes.c_int32(solver.mtype)),
                              solver.iparm.ctypes.data_as(ctypes.c_void_p))
    solver.iparm[34] = 0                            # one-based indices, as pypardiso passes them
    solver.iparm[59] = 2                            # out of core
    folder = tempfile.mkdtemp(prefix="taxel-pardiso-")
    weakref.finalize(solver, shutil.rmtree, folder, ignore_errors=True)
    disk = shutil.disk_usage(folder).free
    if need > 0.9 * disk:
        raise MemoryLimitError(f"the direct solve of {A.shape[0]} unknowns needs about {need / 1e9:.3g} GB, more than "
                               f"the {have / 1e9:.3g} GB free in memory and the {disk / 1e9:.3g} GB free on {folder}'s disk "
                               f"(set TMPDIR to a larger disk); {FIX}")
    os.environ["MKL_PARDISO_OOC_PATH"] = folder
    os.environ["MKL_PARDISO_OOC_MAX_CORE_SIZE"] = str(max(int(0.6 * have / 2**20), 1))
    analysis_bytes(solver, A)
    core = 1024.0 * solver.get_iparm(16)            # what stays in memory out of core too (permanent, KB)
    log.info("PARDISO out of core: %d unknowns, %.3g GB in core against %.3g GB free (%.3g GB permanent)",
             A.shape[0], need / 1e9, have / 1e9, core / 1e9)
    if core > 0.9 * have:
        raise MemoryLimitError(f"the direct solve of {A.shape[0]} unknowns needs about {need / 1e9:.3g} GB in memory "
                               f"and {core / 1e9:.3g} GB out of core, more than the {have / 1e9:.3g} GB free; {FIX}")
