"""The explorer's design solves in worker processes (taxel.explore.workers): the bounded
queue drops a job no page wants, pages asking for one design share one job, a killed
worker costs its job one line and the next job a new pool, and a design is read,
refused or answered in a worker as on the command line."""

from __future__ import annotations

import asyncio
import os
import time

import pytest

from taxel.explore import workers as W


def test_a_job_no_page_wants_is_dropped_and_one_design_asked_twice_is_one_job():
    solvers = W.Solvers(1)

    async def main():
        busy = asyncio.ensure_future(solvers.run("a", lambda: True, time.sleep, 0.3))   # holds the one worker
        await asyncio.sleep(0)
        dropped = asyncio.ensure_future(solvers.run("b", lambda: False, time.time_ns))   # its page moved on
        twice = [asyncio.ensure_future(solvers.run("c", lambda: True, time.time_ns)) for _ in range(2)]
        await asyncio.sleep(0)
        assert len(solvers._flight) == 3                 # "c" once, with its two pages
        return await busy, await dropped, await asyncio.gather(*twice)
    try:
        busy, dropped, (c1, c2) = asyncio.run(main())
    finally:
        solvers.close()
    assert busy is None and dropped is None             # time.sleep's None; the dropped job never ran
    assert isinstance(c1, int) and c1 == c2              # one job, its answer shown to both pages


@pytest.mark.slow          # two pools started: about 4 s (9 s at load average 13)
def test_a_killed_worker_is_one_line_and_the_next_job_gets_a_new_pool():
    solvers = W.Solvers(1)

    async def main():
        with pytest.raises(RuntimeError, match="process was killed") as err:
            await solvers.run("x", lambda: True, os.abort)          # the worker dies mid-job (SIGABRT)
        assert "\n" not in str(err.value)
        return await solvers.run("y", lambda: True, os.getpid)
    try:
        pid = asyncio.run(main())
    finally:
        solvers.close()
    assert isinstance(pid, int) and pid != os.getpid()


def test_a_design_is_refused_or_answered_in_a_worker_as_on_the_command_line(tmp_path):
    import dataclasses

    from taxel.api import load
    from taxel.explore.controls import ControlValues
    from taxel.explore.session import Session
    base = load("thesis-pzt-single-2d")
    design = ControlValues.of(base)
    bad = dataclasses.replace(design, numbers={**design.numbers, "force": "-1"})
    out = W.solve(base, bad, str(tmp_path), W.S.SMALL_UNKNOWNS)
    assert out.answer is None and out.refused[1] == "force" and "force" in out.refused[0]
    ok = W.solve(base, design, str(tmp_path), W.S.SMALL_UNKNOWNS)
    assert ok.refused is None and 0 < ok.unknowns <= W.S.SMALL_UNKNOWNS
    direct = Session(tmp_path / "other").answer(base)    # consistency: the same design solved apart
    assert ok.answer.pressed_voltage == pytest.approx(direct.pressed_voltage, rel=1e-9)
    large = W.solve(base, design, str(tmp_path), 10)                 # over the small size: for the slow lane
    assert large.answer is None and large.refused is None and large.scene is not None
