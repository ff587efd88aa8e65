"""The explorer under attack by a token holder: a real WebSocket client on loopback.

`taxel explore` runs in a subprocess (tests/test_explore_guard.py's fixture); these
clients hold its token and secret and send what a careless paste, a busy page or a
hostile program would: a 1 MB value, frame and chunk headers claiming 4 GB, state
keys of the page's machinery (`trame__scripts`, `extra_busy`), a flood, a negative
force. Each is refused in one logged line, the other pages are answered meanwhile,
and one page's design never reaches another page.
"""

from __future__ import annotations

import os
import shutil
import struct
import time
from pathlib import Path

import pytest
import test_explore_guard as guard
from test_explore_guard import _set, _state, _trigger, _ws, poll_until_state
from waits import CEILING, poll_until

app = guard.app                  # this module's own explorer (a module-scoped fixture)
psutil = pytest.importorskip("psutil")


def _page(app):
    c = _ws(app)
    c.hello()
    poll_until_state(c, app, lambda s: s["voltage"] and not s["busy"], "the page's first answer")
    return c


def _rss(app) -> int:
    return psutil.Process(app.proc.pid).memory_info().rss


def _lines(app, words: str) -> list[str]:
    return [ln for ln in app.log if words in ln]


def test_a_1mb_value_is_refused_before_parsing_while_another_page_is_answered(app):
    a, b = _page(app), _page(app)
    try:
        t0 = time.monotonic()
        _set(a, t_gap="1" * 1_000_000)
        st = poll_until_state(a, app, lambda s: s["e_gap"], "the 1 MB value's refusal")
        refused = time.monotonic() - t0
        assert "1000000 characters; at most 100" in st["e_gap"][0]
        before = _state(b)["voltage"]
        _set(b, t_force="2")                       # the other page's move is answered
        st_b = poll_until_state(b, app, lambda s: not s["busy"] and s["voltage"] != before, "the other page's answer")
        assert st_b["t_force"] == "2"
        print(f"1 MB value refused in {refused * 1e3:.0f} ms")      # benchmarks/explore_load.py times it
        line, = _lines(app, "1000000 characters")
        assert line.count("\n") == 1 and "Traceback" not in "".join(app.log)
    finally:
        a.close()
        b.close()


def _frame_header(length: int) -> bytes:
    """A masked binary WebSocket frame's header claiming `length` bytes of payload."""
    return bytes([0x82, 0x80 | 127]) + struct.pack(">Q", length) + os.urandom(4)


def test_a_4gb_frame_header_is_refused_without_the_allocation(app):
    c = _page(app)
    rss = _rss(app)
    c.ws.sock.sendall(_frame_header(4 << 30) + b"x" * 64)
    poll_until(lambda: _lines(app, "a WebSocket frame"), "the frame's refusal logged", app.proc)
    assert _rss(app) - rss < 100e6
    assert _lines(app, "a WebSocket frame")[-1].count("\n") == 1
    assert "Traceback" not in "".join(app.log)
    c2 = _page(app)                                 # the server goes on
    c2.close()


def test_a_4gb_chunk_header_is_refused_without_the_allocation(app):
    """wslink's own chunk header (12 bytes) claiming 4 GB: two 13-byte frames added 512 MB before."""
    c = _page(app)
    rss = _rss(app)
    for i in range(2):
        try:
            c.ws.send_binary(struct.pack("<III", 7 + i, 0, 0xFFFFFFFF) + b"x")
        except Exception:                           # the server closed the connection after the first
            break
    # the refusal is logged when the header is read, before any allocation it could have made: the
    # logged line is the event to wait for (no fixed sleep)
    poll_until(lambda: _lines(app, "a malformed message"), "the chunk's refusal logged", app.proc)
    assert _rss(app) - rss < 100e6
    assert "exceeds the allocation limit" in _lines(app, "a malformed message")[-1]
    assert "Traceback" not in "".join(app.log)


def _published(c, seconds: float) -> list[dict]:
    """The state pushes a connection receives within `seconds`."""
    import msgpack
    from websocket import WebSocketTimeoutException
    got, end = [], time.monotonic() + seconds
    c.ws.settimeout(0.1)
    try:
        while time.monotonic() < end:
            try:
                frame = c.ws.recv()
            except WebSocketTimeoutException:
                continue
            msg = c.unchunker.process_chunk(frame) if isinstance(frame, bytes) else None
            if msg is not None:
                data = msg if isinstance(msg, dict) else msgpack.unpackb(msg, strict_map_key=False)
                if str(data.get("id", "")).startswith("publish:"):
                    got.append(data.get("result") or {})
    finally:
        c.ws.settimeout(CEILING)
    return got


def test_a_pages_state_never_reaches_another_page(app):
    a, b = _page(app), _page(app)
    try:
        _set(a, t_silicone_above="2", trame__scripts=["http://127.0.0.1:1/evil.js"], extra_busy=True)
        poll_until_state(a, app, lambda s: s["t_silicone_above"] == "2" and not s["busy"], "page a's answer")
        pushed = _published(b, 1.0)
        keys = {k for p in pushed for k in p}
        assert not keys & {"t_silicone_above", "trame__scripts", "extra_busy", "voltage"}, keys
        st_b = _state(b)
        assert st_b["t_silicone_above"] == "1" and st_b["trame__scripts"] != ["http://127.0.0.1:1/evil.js"]
        assert _state(a)["trame__scripts"] != ["http://127.0.0.1:1/evil.js"]
        assert _lines(app, "'trame__scripts' (not a control of this page)")
        assert _lines(app, "'extra_busy' (not a control of this page)")
    finally:
        a.close()
        b.close()


@pytest.mark.slow
def test_a_flood_is_bounded_and_figures_queue_one_per_page(app):
    """700 moves and 6 figure requests sent without waiting: the flood is paced (one line),
    one figure is made (the others refused), and another page is answered meanwhile."""
    a, b = _page(app), _page(app)
    try:
        section = "trigger__5"                      # the "section" button (its id "section")
        assert f"trigger('{section}'" in _state(a)["trame__template_main"].split('id="section"')[1][:300]
        for _ in range(6):
            a.send("trame.trigger", section, [], {})
        for i in range(700):
            a.send("trame.state.update", [{"key": "t_silicone_above", "value": f"{0.5 + (i % 40) * 0.05:.2f}"}])
        before = _state(b)["voltage"]
        _set(b, t_force="3")
        poll_until_state(b, app, lambda s: not s["busy"] and s["voltage"] != before, "the other page's answer")
        st = poll_until_state(a, app, lambda s: not s["busy"] and not s["extra_busy"] and s["figure"],
                              "the flooding page's last answer and its figure")
        assert st["t_silicone_above"] == f"{0.5 + (699 % 40) * 0.05:.2f}"
        assert _lines(app, "messages a second: read slower")
        assert len(_lines(app, "a figure is being made for this page already")) >= 1
    finally:
        a.close()
        b.close()


def test_force_minus_one_and_gap_minus_one_are_refused_as_on_the_command_line(app):
    c = _page(app)
    try:
        for key, field in (("t_force", "e_force"), ("t_gap", "e_gap")):
            _set(c, **{key: "-1"})
            st = poll_until_state(c, app, lambda s, f=field: s[f], f"the refusal of {key} = -1")
            assert ("load.force" if key == "t_force" else "array.gap") in st[field][0]
            _set(c, **{key: "1" if key == "t_force" else "3"})
            poll_until_state(c, app, lambda s, f=field: not s[f] and not s["busy"], "the design back")
        assert _lines(app, "refused from connection") and "Traceback" not in "".join(app.log)
    finally:
        c.close()


WRITES = ("openat", "open", "creat", "mkdir", "mkdirat", "rename", "renameat", "renameat2", "unlink", "unlinkat",
          "truncate", "link", "linkat", "symlink", "symlinkat")


def _written(trace: Path, cwd: Path) -> set[Path]:
    """The paths a traced process tree created, wrote, renamed or removed (calls that succeeded)."""
    import re
    found = set()
    for line in trace.read_text(errors="replace").splitlines():
        m = re.match(r"\d+\s+(\w+)\((.*)\)\s+=\s+(-?\d+)", line)
        if not m or m.group(1) not in WRITES or int(m.group(3)) < 0:
            continue
        name, args = m.group(1), m.group(2)
        if name.startswith("open") and not re.search(r"O_WRONLY|O_RDWR|O_CREAT|O_TRUNC", args):
            continue
        base = re.match(r"\d+<([^>]*)>", args)         # an *at call's directory (strace -y)
        for p in re.findall(r'"((?:[^"\\]|\\.)*)"', args):
            found.add(Path(p) if p.startswith("/") else (Path(base.group(1)) if base else cwd) / p)
    return found


@pytest.mark.slow
@pytest.mark.skipif(not shutil.which("strace"), reason="no strace here")
def test_no_process_of_the_explorer_writes_outside_its_output_folder(tmp_path):
    """The explorer, its page's work (an answer, a figure, a saved scene) and a 3D worker, traced
    with strace -f: every file they create, write, rename or remove is under the output folder
    (gmsh's FLTK preferences included: meshing.build, taxel.explore.confine)."""
    from wslink_client import Client, page_secret

    from taxel.explore.browser import ExplorerProcess
    out, trace = tmp_path / "out", tmp_path / "trace"
    with ExplorerProcess("thesis-pzt-single-2d", out, CEILING, cwd=tmp_path, env={"PYTHONDONTWRITEBYTECODE": "1"},
                         prefix=("strace", "-f", "-qq", "-y", "-e", f"trace={','.join(WRITES)}", "-o", str(trace))) as app:
        app.root = tmp_path
        tok = app.url.split("token=")[1]
        c = Client(f"ws://127.0.0.1:{app.port}/ws?token={tok}", origin=f"http://127.0.0.1:{app.port}",
                   secret=page_secret(app.url))
        c.hello()
        try:
            poll_until_state(c, app, lambda s: s["voltage"] and not s["busy"], "the first answer")
            _trigger(c, "trigger__5")                                   # section
            _trigger(c, "trigger__1")                                   # save scene TOML
            _trigger(c, "trigger__4")                                   # solve in 3D (a worker process)
            poll_until_state(c, app, lambda s: s["answer3d"] and s["figure"], "the 3D answer and the figure")
        finally:
            c.close()
    text = trace.read_text(errors="replace")
    assert text.count("fltk.prefs") >= 2                 # gmsh started under the trace (the explorer, the worker)
    written = _written(trace, tmp_path)
    allowed = (out.resolve(), Path("/dev"), Path("/proc"))
    outside = sorted(str(p) for p in written if not any(p.resolve().is_relative_to(a) for a in allowed))
    assert any(p.resolve().is_relative_to(out.resolve()) for p in written)    # the trace saw the writes
    assert not outside, outside[:10]
