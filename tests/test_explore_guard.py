"""Who may reach `taxel explore`, and what a crafted client can do: a real WebSocket client.

`taxel explore` runs in a subprocess on a free port; this test talks to it as any
program on the machine could, over HTTP and its WebSocket (/ws, trame's wslink
protocol: tests/wslink_client.py). Without the printed token, with a foreign Origin or
a foreign Host the connection is refused (HTTP 403, one line in the server's log).
With the token, crafted messages (paths with `..`, absurd values, values of the wrong
type, a flood of moves, triggers with absurd arguments) write nothing outside the
output folder and leave the server answering.
"""

from __future__ import annotations

import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest
from waits import CEILING, poll_until
from wslink_client import Client, HandshakeRefused, page_secret

from taxel.explore.browser import ExplorerProcess

SCENE = "thesis-pzt-single-2d"


@pytest.fixture(scope="module")
def app(tmp_path_factory):
    root = tmp_path_factory.mktemp("explore-guard")
    with ExplorerProcess(SCENE, root / "out", CEILING, cwd=root) as proc:
        proc.root = root
        proc.secret = page_secret(proc.url)
        keep = _ws(proc)          # trame ends a server left without a client: one stays connected
        keep.hello()
        yield proc
        keep.close()


def _ws(app, token=True, origin="same", host=None):
    tok = app.url.split("token=")[1]
    url = f"ws://127.0.0.1:{app.port}/ws" + (f"?token={tok}" if token else "")
    return Client(url, origin=f"http://127.0.0.1:{app.port}" if origin == "same" else origin, host=host,
                  secret=getattr(app, "secret", "wslink-secret"))


def _refusals(app, words):
    poll_until(lambda: any("refused" in ln and words in ln for ln in app.log), f"the refusal '{words}' logged",
               app.proc)
    return [ln for ln in app.log if "refused" in ln and words in ln]


def test_a_websocket_without_the_token_is_refused(app):
    with pytest.raises(HandshakeRefused) as err:
        _ws(app, token=False)
    assert err.value.status == 403
    line, = _refusals(app, "GET /ws")[:1]
    assert "no valid token" in line and line.count("\n") == 1


def test_a_websocket_with_a_foreign_origin_is_refused_even_with_the_token(app):
    with pytest.raises(HandshakeRefused) as err:
        _ws(app, origin="http://evil.example")
    assert err.value.status == 403
    _refusals(app, "Origin 'http://evil.example'")


def test_a_foreign_host_is_refused_dns_rebinding(app):
    with pytest.raises(HandshakeRefused):
        _ws(app, host=f"evil.example:{app.port}", origin=f"http://evil.example:{app.port}")
    _refusals(app, "Host 'evil.example")


def test_the_page_needs_the_token_and_the_token_sets_a_cookie_that_is_not_the_token(app):
    """The printed address is answered by a redirect to the page with this run's wslink secret
    (never wslink's public default) and a cookie named after the port holding an HMAC of the
    token: the cookie another port of 127.0.0.1 receives is not the token."""
    base = f"http://127.0.0.1:{app.port}/index.html"
    with pytest.raises(urllib.error.HTTPError) as err:
        urllib.request.urlopen(base, timeout=CEILING)
    assert err.value.code == 403
    token = app.url.split("token=")[1]

    class Stop(urllib.request.HTTPRedirectHandler):
        def redirect_request(self, *a, **k):
            return None
    with pytest.raises(urllib.error.HTTPError) as err:
        urllib.request.build_opener(Stop).open(base + "?token=" + token, timeout=CEILING)
    assert err.value.code == 302
    cookie, where = err.value.headers["Set-Cookie"], err.value.headers["Location"]
    assert f"taxel-explore-{app.port}=" in cookie and "HttpOnly" in cookie and "SameSite=Strict" in cookie
    assert token not in cookie and token not in where
    secret = where.split("secret=")[1]
    assert secret != "wslink-secret" and len(secret) >= 32 and secret == app.secret
    req = urllib.request.Request(f"http://127.0.0.1:{app.port}{where}", headers={"Cookie": cookie.split(";")[0]})
    with urllib.request.urlopen(req, timeout=CEILING) as r:
        assert r.status == 200
    c = _ws(app)                                     # the public default secret no longer opens the WebSocket
    try:
        assert "error" in c.hello("wslink-secret")
    finally:
        c.close()


def test_with_the_token_and_its_own_origin_the_websocket_opens(app):
    c = _ws(app)
    try:
        assert "clientID" in c.hello()["result"]
    finally:
        c.close()


def _state(c: Client) -> dict:
    return c.call("trame.state.get")["result"]["state"]


def _set(c: Client, **values) -> None:
    c.call("trame.state.update", [{"key": k, "value": v} for k, v in values.items()])


def _trigger(c: Client, name: str, *args) -> dict:
    return c.call("trame.trigger", name, list(args), {})


def _files(root: Path) -> set[Path]:
    return {p for p in root.rglob("*") if p.is_file()}


def test_crafted_messages_write_nothing_outside_the_output_folder(app):
    c = _ws(app)
    c.hello()
    try:
        poll_until(lambda: _state(c)["voltage"], "the first answer", app.proc)
        outside = _files(app.root) - _files(app.root / "out")
        export = "trigger__1"                     # the "save scene TOML" button (its id "export")
        assert "trigger('trigger__1'" in _state(c)["trame__template_main"].split('id="export"')[1][:300]
        for name in ["../../escape", "..", "/tmp/escape", "a/../../b", "x" * 5000, "", "ok\x00x", ["a"], {"a": 1}]:
            _set(c, export_name=name)
            _trigger(c, export)
            assert "not a file name" in _state(c)["export_msg"], name
        _set(c, export_name="kept")
        _trigger(c, export)
        assert _state(c)["export_msg"].startswith("wrote ")
        assert (app.root / "out" / "exports" / "kept.toml").is_file()
        # the other triggers with absurd arguments: the front's row (none here), send, a huge index
        for args in [(10 ** 12,), ("../x",), (-1,), ({"i": 1},)]:
            _trigger(c, "trigger__2", *args)
        _trigger(c, "trigger__3")
        assert _files(app.root) - _files(app.root / "out") == outside
    finally:
        c.close()
    assert app.proc.poll() is None


def test_absurd_values_are_refused_in_one_line_and_the_server_goes_on(app):
    c = _ws(app)
    c.hello()
    keys = ("t_silicone_above", "t_taxel_width", "model", "piezo")
    first = _state(c)
    try:
        for key, value, words in [("t_silicone_above", "nan", "silicone_above"),
                                  ("t_silicone_above", "-3", "silicone_above"),
                                  ("t_silicone_above", {"$gt": 1}, "silicone_above"),
                                  ("t_taxel_width", "1e9", "taxel_width"),
                                  ("model", "../../etc", "model"),
                                  ("piezo", ["PZT-5H"] * 1000, "piezo")]:
            _set(c, **{key: value})
            st = poll_until_state(c, app, lambda s: s["message"] or any(s[f"e_{n}"] for n in ("silicone_above",
                                  "taxel_width", "piezo")), f"the refusal of {key} = {str(value)[:20]}")
            shown = " ".join([st["message"], *st["e_silicone_above"], *st["e_taxel_width"], *st["e_piezo"]])
            assert words in shown and "\n" not in shown and "Traceback" not in shown, shown
            _set(c, **{k: first[k] for k in keys})
            poll_until_state(c, app, lambda s: not s["message"] and not s["e_silicone_above"]
                             and not s["e_taxel_width"] and not s["busy"], "the design back")
    finally:
        c.close()


def poll_until_state(c, app, predicate, what):
    box = {}

    def check():
        box["s"] = _state(c)
        return predicate(box["s"])
    poll_until(check, what, app.proc, every=0.1)
    return box["s"]


def test_a_flood_of_moves_is_answered_once_with_the_newest(app):
    """800 moves sent without waiting (past the pace of 500 a second): one update loop, one
    solve waiting (the newest); the answer shown is the last value's, and the server answers
    at once afterwards."""
    c = _ws(app)
    c.hello()
    try:
        for i in range(800):
            c.send("trame.state.update", [{"key": "t_silicone_above", "value": f"{0.5 + (i % 40) * 0.05:.2f}"}])
        _set(c, t_silicone_above="1.55")
        st = poll_until_state(c, app, lambda s: not s["busy"] and s["voltage"] and not s["message"],
                              "the answer after the flood")
        t0 = time.monotonic()
        _state(c)
        assert time.monotonic() - t0 < CEILING
    finally:
        c.close()
    c2 = _ws(app)                 # a second connection has its own design: the base scene's
    c2.hello()
    try:
        assert _state(c2)["t_silicone_above"] == "1"
    finally:
        c2.close()
    assert st["voltage"] and app.proc.poll() is None
    assert any("messages a second: read slower" in ln for ln in app.log)      # the flood was paced


def test_a_solve_that_would_not_fit_is_refused_with_its_size():
    """The explorer's memory cap (session.MEMORY_3D of this machine) on the 3D solve it
    would start, and on any solve: refused before it starts, with its size."""
    import taxel
    from taxel.explore import session as S
    scene = S.coarse_3d(taxel.load(SCENE))
    cost = S.check_fits(scene)                      # the coarse 3D model fits this machine
    assert 0 < cost.bytes <= S.MEMORY_3D * cost.memory
    with pytest.raises(S.TooLarge) as err:
        S.check_fits(scene, share=0.5 * cost.bytes / cost.memory)
    msg = str(err.value)
    assert "3D" in msg and f"{cost.unknowns:.3g} unknowns" in msg and "GB" in msg and "\n" not in msg


def test_the_host_is_checked_on_every_bind_and_the_cookie_is_per_port():
    """A bind on every interface still refuses a Host that is not this machine's (DNS
    rebinding of a name to this machine's address); two ports' cookies differ, and neither
    is the token."""
    import socket

    from aiohttp.test_utils import make_mocked_request

    from taxel.explore.guard import Guard
    g = Guard("0.0.0.0", 8123, "t0ken")

    def why(host):
        return g.why_refused(make_mocked_request("GET", "/?token=t0ken", headers={"Host": host}))
    assert why("127.0.0.1:8123") is None and why(f"{socket.gethostname()}:8123") is None
    assert "DNS rebinding" in why("evil.example:8123") and "DNS rebinding" in why("127.0.0.1:9999")
    other = Guard("0.0.0.0", 8124, "t0ken")
    assert g.cookie != other.cookie and g.cookie_value() != other.cookie_value()
    assert "t0ken" not in g.cookie_value() and g.secret != "wslink-secret"


def test_the_memory_caps_add_up():
    """The 3D solve, the slow lane's 2D solve and the fast lane's small solves, all at once,
    within the explorer's budget of this machine's memory (taxel.explore.session)."""
    from taxel.explore import app as A
    from taxel.explore import session as S
    from taxel.meshing.cost import unknowns_cost
    small = unknowns_cost(S.SMALL_UNKNOWNS, 2)
    total = S.MEMORY_3D + S.MEMORY_2D + A.FAST_WORKERS * small.bytes / small.memory
    assert total <= S.MEMORY_BUDGET < 0.5
