"""The explorer's design solves in processes: each worker its own interpreter and gmsh.

A page's new design is read (controls.scene_of: the scene schema's checks), its cost
checked against the 2D cap and, when small (session.SMALL_UNKNOWNS), solved in one of
`size` worker processes (`Solvers`), so the solves of several pages run on several
cores at once: threads of one process shared its interpreter lock and gmsh's one
model (meshing.build meshes one model at a time per process). A large design comes
back unsolved, for the explorer's slow lane.

Bounded and cancellable: at most `size` jobs are in the processes at once; the others
wait on the event loop, and a job that no page wants any more when its turn comes
(each page that asked for it moved on or closed) is dropped before it reaches a
process. A job already in a process runs to its end (a small solve: well under a
second) and its answer goes to the study store, where a later page finds it; the page
that moved on is not shown it. Pages asking for the same design at once share one job
(coalesced, `Solvers.run`'s key). A worker killed mid-solve (out of memory) ends the
pool: that job's pages get one line, and the next job starts a new pool.

Confinement: the workers are spawned by the explorer's process after
taxel.explore.confine pointed HOME, TMPDIR and the caches into the output folder, so
they inherit that private home; gmsh starts in them as in any process (meshing.build:
setfsuid(nobody) around its start where the process is root). Memory: each worker is
an interpreter with the solver's libraries, WORKER_BYTES, plus one small solve
(session.MEMORY_BUDGET counts both). A worker ends itself when the explorer's process
is gone (a parent killed by a signal leaves no worker behind).
"""

from __future__ import annotations

import asyncio
import multiprocessing
import os
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass

from taxel.explore import session as S
from taxel.explore.controls import ControlValues, FieldError, scene_of
from taxel.scene import Scene

# a worker's memory besides its solve: an interpreter with numpy, scipy, scikit-fem, gmsh,
# pint and taxel imported, 0.15-0.16 GB resident after a run of benchmarks/explore_load.py
# (its worker_rss_max_bytes), rounded up
WORKER_BYTES = 0.2e9
MAX_WORKERS = 4


def count() -> int:
    """How many workers: one per core (at most MAX_WORKERS), and no more than fit, each
    WORKER_BYTES and one solve of session.SMALL_UNKNOWNS, in what session.MEMORY_BUDGET
    leaves beside the 3D solve (MEMORY_3D) and the slow lane's (MEMORY_2D); at least one."""
    from taxel.meshing.cost import unknowns_cost
    small = unknowns_cost(S.SMALL_UNKNOWNS, 2)
    room = (S.MEMORY_BUDGET - S.MEMORY_3D - S.MEMORY_2D) * small.memory
    return max(1, min(os.cpu_count() or 1, MAX_WORKERS, int(room // (small.bytes + WORKER_BYTES))))


@dataclass
class Outcome:
    """A design read and, when small, answered in a worker: `scene` and `answer`; a
    large one has no answer (the slow lane solves it); a refused one, `refused`."""

    scene: Scene | None = None
    answer: S.Answer | None = None
    refused: tuple[str, str | None] | None = None      # (one-line message, the control)
    unknowns: float = 0.0


def prepare(base: Scene, design: ControlValues) -> tuple[Scene, object]:
    """The design's scene and solve cost; FieldError (one line) where it is refused."""
    try:
        scene = scene_of(base, design)
        return scene, S.check_fits(scene, S.MEMORY_2D)
    except FieldError:
        raise
    except Exception as exc:                        # TooLarge, or a value no control makes
        raise FieldError(str(exc).splitlines()[0] if str(exc) else type(exc).__name__, None) from None


_SESSION: S.Session | None = None


def _start(parent: int) -> None:
    """A worker's start: the solver's modules imported, and a watch on the explorer."""
    import gmsh  # noqa: F401
    import skfem  # noqa: F401

    import taxel.analyses  # noqa: F401

    def watch():
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(0)
    threading.Thread(target=watch, daemon=True, name="explore-worker-watch").start()


def solve(base: Scene, design: ControlValues, store: str, small: float) -> Outcome:
    """In a worker: the design read, checked and, when at most `small` unknowns, answered."""
    global _SESSION
    try:
        scene, cost = prepare(base, design)
    except FieldError as exc:
        return Outcome(refused=(str(exc), exc.field))
    if cost.unknowns > small:
        return Outcome(scene, None, None, cost.unknowns)
    if _SESSION is None:
        _SESSION = S.Session(store)
    return Outcome(scene, _SESSION.answer(scene), None, cost.unknowns)


class Solvers:
    """`size` worker processes and the event loop's bounded queue in front of them."""

    def __init__(self, size: int):
        self.size = size
        self._pool: ProcessPoolExecutor | None = None
        self._slots: asyncio.Semaphore | None = None
        self._flight: dict = {}                       # key -> (job task, [wanted() of each page])

    def pool(self) -> ProcessPoolExecutor:
        if self._pool is None:
            self._pool = ProcessPoolExecutor(self.size, mp_context=multiprocessing.get_context("spawn"),
                                             initializer=_start, initargs=(os.getpid(),))
        return self._pool

    def start(self) -> None:
        """Spawn the workers now (each imports the solver's libraries), not at the first move."""
        for _ in range(self.size):
            self._submit(time.sleep, 0.2)

    def _submit(self, fn, *args):
        """pool().submit, with Ctrl-C ignored in the workers it spawns: the explorer ends
        them (a worker interrupted as well, importing, printed a traceback). An ignored
        SIGINT is inherited, and Python then installs no KeyboardInterrupt for it."""
        import signal
        if threading.current_thread() is not threading.main_thread():
            return self.pool().submit(fn, *args)
        old = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            return self.pool().submit(fn, *args)
        finally:
            signal.signal(signal.SIGINT, old)

    async def run(self, key, wanted, fn, *args):
        """fn(*args) in a worker, once per key at a time; None when dropped (no page
        wanted it when its turn came). `wanted()`: whether the asking page still does."""
        flight = self._flight.get(key)
        if flight is None:
            job = asyncio.get_running_loop().create_task(self._job(key, fn, args))
            job.add_done_callback(lambda t: t.cancelled() or t.exception())    # read, when no page waits
            flight = self._flight[key] = (job, [])
        flight[1].append(wanted)
        return await asyncio.shield(flight[0])

    async def _job(self, key, fn, args):
        if self._slots is None:
            self._slots = asyncio.Semaphore(self.size)
        try:
            async with self._slots:
                if not any(w() for w in self._flight[key][1]):
                    return None                       # dropped before it reached a process
                pool = self.pool()
                try:
                    return await asyncio.wrap_future(self._submit(fn, *args))
                except BrokenProcessPool:
                    if self._pool is pool:
                        self._pool = None             # the next job starts a new pool
                        pool.shutdown(wait=False, cancel_futures=True)
                    raise RuntimeError("the solve's process was killed (out of memory?); "
                                       "move a control to solve again") from None
        finally:
            self._flight.pop(key, None)

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._pool = None
