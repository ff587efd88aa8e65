"""Faults in the explorer: its 3D solve's process killed by SIGKILL mid-solve (as the
kernel's out-of-memory killer would). The page says so in one line and recovers: the
2D answers go on, a new 3D solve starts, and the explorer's store keeps every point
it had finished. Driven as the page drives it, over its WebSocket (tests/wslink_client.py).
"""

from __future__ import annotations

import os
import signal

import pytest
import test_explore_guard as guard
from test_explore_guard import _set, _trigger, _ws, poll_until_state
from waits import poll_until

app = guard.app                  # this module's own explorer (a module-scoped fixture)

psutil = pytest.importorskip("psutil")

SOLVE_3D = "trigger__4"          # the "solve in 3D" button (its id "solve3d")


def _stored(server) -> int:
    from taxel.studies.store import Store
    store = Store(server.root / "out" / "store")
    try:
        return sum(r["status"] == "done" for r in store.rows())
    finally:
        store.close()


def _solver_child(server):
    """The 3D solve's process: a child of the explorer running multiprocessing's spawn."""
    kids = [p for p in psutil.Process(server.proc.pid).children() if "multiprocessing" in " ".join(p.cmdline())
            and "resource_tracker" not in " ".join(p.cmdline())]
    return kids[0] if kids else None


def test_a_3d_solve_killed_mid_solve_is_reported_and_the_explorer_recovers(app):
    c = _ws(app)
    c.hello()
    try:
        st = poll_until_state(c, app, lambda s: s["voltage"] and not s["busy"], "the first answer")
        assert "trigger('trigger__4'" in st["trame__template_main"].split('id="solve3d"')[1][:300]
        before = _stored(app)
        assert before >= 1
        _trigger(c, SOLVE_3D)
        poll_until(lambda: _solver_child(app) is not None, "the 3D solve's process", app.proc)
        child = _solver_child(app)
        os.kill(child.pid, signal.SIGKILL)
        st = poll_until_state(c, app, lambda s: not s["busy3d"] and s["answer3d"], "the page's word on the kill")
        assert "killed (SIGKILL" in st["answer3d"] and "\n" not in st["answer3d"], st["answer3d"]
        assert st["progress3d"] == "3D solve done"
        assert _stored(app) >= before                          # every finished point kept
        # it recovers: a new design is answered, and a new 3D solve starts (cancelled by the next move)
        _set(c, t_force=f"{float(st['t_force']) * 1.1:.2f}")
        poll_until_state(c, app, lambda s: not s["busy"] and s["voltage"] != st["voltage"], "a new answer")
        _trigger(c, SOLVE_3D)
        poll_until_state(c, app, lambda s: s["busy3d"], "a new 3D solve")
        _set(c, t_force=st["t_force"])
        poll_until_state(c, app, lambda s: not s["busy3d"] and "cancelled" in s["progress3d"], "the cancel")
        assert _stored(app) >= before + 1 and app.proc.poll() is None
    finally:
        c.close()
