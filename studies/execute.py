"""Running a study: every point not already in the store, in-process or on Dask,
with progress; results are stored as they finish (studies.store)."""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import time
from dataclasses import dataclass
from pathlib import Path

from taxel.scene import SceneError
from taxel.studies.evaluate import evaluate_safely
from taxel.studies.spec import Study, StudyError
from taxel.studies.store import Store, point_key


@dataclass
class RunSummary:
    total: int
    cached: int
    done: int
    failed: int
    seconds: float


def run(study: Study, out: Path, workers: int = 2, scheduler: str | None = None,
        retry_failed: bool = False, progress: bool = True) -> RunSummary:
    """Run every point not already in the store (in-process for workers = 1, else on
    a local Dask cluster or the one at `scheduler`); the store stays with the caller."""
    t0 = time.perf_counter()
    with exclusive(out):
        return _run(study, out, workers, scheduler, retry_failed, progress, t0)


@contextlib.contextmanager
def exclusive(folder: Path):
    """Hold the folder's run lock (results.lock, flock) for the whole run: a second
    `taxel study run` on the same folder is refused at once instead of computing
    every point again. The OS drops the lock when the process dies (kill -9 too)."""
    folder.mkdir(parents=True, exist_ok=True)
    fh = open(folder / "results.lock", "a+")
    try:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        fh.close()
        raise StudyError(f"{folder}: another study run is writing this folder; wait for it to finish "
                         "(or stop it) and run again, or use another --out") from None
    try:
        yield
    finally:
        fcntl.flock(fh, fcntl.LOCK_UN)
        fh.close()


def _run(study, out, workers, scheduler, retry_failed, progress, t0) -> RunSummary:
    store = Store(out)
    points = study.points()
    todo, params_of, cached = [], {}, 0
    known = store.status()
    seen, invalid = set(), set()
    for pt in points:
        data = study.scene_data(pt)
        try:
            key = point_key(data)
        except SceneError as exc:        # stored failed, and counted: the run exits 1
            key = hashlib.sha256(json.dumps(data, sort_keys=True).encode()).hexdigest()
            if key not in known:
                store.put(key, pt, "failed", error=f"SceneError: {exc}")
            invalid.add(key)
            continue
        if key in seen:
            continue
        seen.add(key)
        params_of[key] = pt
        st = known.get(key)
        if st == "done" or (st == "failed" and not retry_failed):
            cached += 1
            continue
        todo.append((key, data))
    outputs = tuple(study.spec.outputs)
    done = failed = 0
    bar = progress_bar(len(seen), cached, progress)
    try:
        for key, (status, result, error) in _execute(todo, outputs, workers, scheduler):
            store.put(key, params_of[key], status, result, error, (result or {}).get("seconds", 0.0))
            done += status == "done"
            failed += status == "failed"
            bar.update(1)
            bar.set_postfix(done=done, failed=failed, cached=cached)
    finally:
        bar.close()
        store.close()
    return RunSummary(len(seen) + len(invalid), cached, done, failed + len(invalid), time.perf_counter() - t0)


def progress_bar(total, cached, progress):
    """A study's progress bar of points (tqdm), drawn only when stderr is a terminal."""
    from tqdm import tqdm
    # only on a terminal (tqdm's disable=None): a log gets the caller's one line per stage, not
    # carriage-return bars
    bar = tqdm(total=total, initial=cached, disable=None if progress else True, unit="point", dynamic_ncols=True)
    bar.set_postfix(done=0, failed=0, cached=cached)
    return bar


def _execute(todo, outputs, workers, scheduler):
    """Yield (key, (status, result, error)) as points finish."""
    if not todo:
        return
    if workers <= 1 and scheduler is None:
        for key, data in todo:
            yield key, evaluate_safely(data, outputs)
        return
    import distributed  # noqa: F401  (configures its loggers on import: before _quiet_client)
    with _quiet_client():
        yield from _execute_dask(todo, outputs, workers, scheduler)


@contextlib.contextmanager
def _quiet_client():
    """The Dask client logs a lost scheduler as tracebacks on stderr; the run reports
    it in one line (SchedulerLost), so the client's own log is silenced meanwhile, and
    stays so after a failed run (the client's loop thread logs its closing later)."""
    import logging
    log = logging.getLogger("distributed.client")
    level = log.level
    log.setLevel(logging.CRITICAL)
    yield
    log.setLevel(level)


def _execute_dask(todo, outputs, workers, scheduler):
    """Yield (key, (status, result, error)) from Dask as chunks of points finish. A
    chunk whose worker died (more often than the scheduler's allowed-failures) is
    recorded failed; a lost scheduler raises SchedulerLost."""
    from dask.distributed import Client, as_completed
    from distributed import KilledWorker
    if scheduler is not None:
        try:
            client, cluster = Client(scheduler, timeout="10s"), None
        except (OSError, TimeoutError, ValueError) as exc:
            raise StudyError(f"--scheduler {scheduler}: cannot reach it ({str(exc).splitlines()[0][:120]}); "
                             "check the address, or drop --scheduler to use local workers") from None
        n_workers = max(len(client.scheduler_info()["workers"]), 1)
    else:
        cluster = local_cluster(workers)
        client = Client(cluster)
        n_workers = workers
    try:
        client.run(_single_threaded)
        # a few points per task: fewer round trips, results still stored as they come
        size = max(1, min(4, len(todo) // (8 * n_workers)))
        chunks = [todo[i:i + size] for i in range(0, len(todo), size)]
        futures = {client.submit(_evaluate_chunk, chunk, outputs, pure=False): chunk for chunk in chunks}
        finished = 0
        for fut in as_completed(list(futures)):
            try:
                results = fut.result()
            except KilledWorker:               # its worker died every time it ran (kill -9, out of memory)
                results = [(key, ("failed", None, f"WorkerDied: {_worker_died()}")) for key, _ in futures[fut]]
            except Exception as exc:           # the scheduler went away: every future is cancelled
                if client.status == "running" and "Cancelled" not in type(exc).__name__:
                    raise                          # not the machinery: a bug (points catch their own errors)
                raise SchedulerLost(f"the Dask scheduler{' at ' + scheduler if scheduler else ''} was lost "
                                    f"({type(exc).__name__}) after {finished} of {len(todo)} points; the finished "
                                    "points are stored: run 'taxel study run' again to resume") from None
            finished += len(results)
            yield from results
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


class SchedulerLost(RuntimeError):
    """The Dask scheduler disappeared mid-run; the finished points are stored and a
    rerun resumes. One line (exit 1 at the command line)."""


def _worker_died() -> str:
    import dask
    tries = dask.config.get("distributed.scheduler.allowed-failures") + 1
    return (f"the Dask worker computing this point died {tries} time(s) (killed, or out of memory); "
            "run again with --retry-failed, or with fewer --workers if memory is short")


# Modules a worker needs, imported once in the fork server so every worker starts warm.
WORKER_PRELOAD = ("taxel.studies.evaluate", "taxel.analyses.solves.analysis", "taxel.analyses.model.problem", "taxel.analyses.solves.dynamic")


def start_method() -> str:
    """How to start workers: "fork" from a single-threaded caller (a `taxel` command,
    a plain script): they start in a fraction of a second with the FEM stack loaded.
    "forkserver" when the caller runs other threads (a notebook kernel, a GUI, a
    program with a reader thread): forking such a caller copies locks those threads
    may hold, and its workers deadlocked in the test suite after the pty tests; a
    fork server is a clean single-threaded process that preloads the FEM stack once
    (`WORKER_PRELOAD`; a few seconds, paid once per process)."""
    import threading
    return "fork" if threading.active_count() == 1 else "forkserver"


def map_on_workers(fn, calls: list[tuple], workers: int) -> list:
    """`fn(*args)` for each args tuple of `calls`, in order: on a local Dask cluster of
    `workers` processes (local_cluster) when there are two or more calls and workers,
    else in this process. The cluster lives for this call only."""
    if workers > 1 and len(calls) > 1:
        from dask.distributed import Client
        cluster = local_cluster(min(workers, len(calls)))
        client = Client(cluster)
        try:
            return client.gather([client.submit(fn, *args, pure=False) for args in calls])
        finally:
            client.close()
            cluster.close()
    return [fn(*args) for args in calls]


def local_cluster(workers: int, method: str | None = None):
    """A local Dask cluster for FEM work: one process per worker (gmsh is not
    thread-safe), one thread and one BLAS thread each, started by `start_method()`
    unless `method` is given. Measured by benchmarks/study_workers.py (cluster
    start and the 70-point Fig. 2.5 study on 2 workers, 2 cores); spawned workers
    start cold. The statistical profiler is off (no measurable effect either way)."""
    import dask
    from dask.distributed import LocalCluster
    method = method or start_method()
    one = {v: "1" for v in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS")}
    with dask.config.set({"distributed.worker.profile.enabled": False,
                          "distributed.worker.multiprocessing-method": method}):
        if method == "forkserver":
            _preload_fork_server()
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, env=one,
                            dashboard_address=None, silence_logs=40)


def _preload_fork_server():
    """Preload Dask and the FEM stack in the fork server. Dask's `get_mp_context`
    sets its own list once per process; ours replaces it after (it takes effect
    when the server starts, at the first cluster of a process)."""
    from distributed.utils import get_mp_context
    get_mp_context().set_forkserver_preload(["distributed", *WORKER_PRELOAD])


def _evaluate_chunk(chunk, outputs):
    return [(key, evaluate_safely(data, outputs)) for key, data in chunk]


def _single_threaded():
    """One BLAS/MKL thread per worker (the workers are the parallelism)."""
    import os
    for var in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        os.environ[var] = "1"
    try:
        from threadpoolctl import threadpool_limits
        threadpool_limits(1)
    except ImportError:
        pass
