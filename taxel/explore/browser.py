"""Headless Chromium over the Chrome DevTools protocol: drive and time the page.

Used by the explorer's browser test and its latency benchmark (and to take the
guide's screenshot). Chromium is Debian's `/usr/bin/chromium` (or $CHROMIUM);
the protocol goes over a websocket (the `websocket-client` package). Key presses
are real input events (`Input.dispatchKeyEvent`), so a slider moves as under a
hand; timings are taken in the page (performance.now()).
"""

from __future__ import annotations

import base64
import json
import os
import shutil
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path


def chromium_path() -> str | None:
    """The Chromium executable, or None when it is not installed."""
    return os.environ.get("CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")


class Browser:
    """One headless Chromium with one page; `call` sends a DevTools command."""

    def __init__(self, width: int = 1400, height: int = 1000, timeout: float = 120.0):
        import websocket
        exe = chromium_path()
        if exe is None:
            raise RuntimeError("no Chromium: install Debian's chromium (apt-get install chromium)")
        self.profile = tempfile.mkdtemp(prefix="taxel-chromium-")
        self.proc = subprocess.Popen(
            [exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
             "--disable-component-update", "--disable-sync", "--no-first-run", "--remote-debugging-port=0",
             f"--user-data-dir={self.profile}", f"--window-size={width},{height}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        port = None
        for line in self.proc.stderr:           # Chromium prints its DevTools address when it is ready
            if "DevTools listening on" in line:
                port = int(line.rsplit(":", 1)[1].split("/")[0])
                break
        if port is None:
            self.close()
            raise RuntimeError("Chromium exited before it listened for DevTools")
        pages = json.loads(urllib.request.urlopen(f"http://127.0.0.1:{port}/json", timeout=timeout).read())
        page = next(p for p in pages if p["type"] == "page")
        self.ws = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=timeout)
        self.timeout, self._id = timeout, 0

    def call(self, method: str, **params) -> dict:
        self._id += 1
        self.ws.send(json.dumps({"id": self._id, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == self._id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})

    def js(self, expression: str):
        """The value of a JavaScript expression in the page (promises awaited)."""
        r = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in r:
            raise RuntimeError(f"page script failed: {r['exceptionDetails'].get('text')} in {expression[:80]}")
        return r["result"].get("value")

    def goto(self, url: str) -> None:
        self.call("Page.enable")
        self.call("Page.navigate", url=url)

    def wait(self, expression: str, limit: float | None = None, what: str = "") -> object:
        """Poll a JavaScript expression until it is truthy; its value. Raises
        TimeoutError after `limit` s (default: the browser's timeout)."""
        end = time.monotonic() + (limit or self.timeout)
        while time.monotonic() < end:
            try:
                v = self.js(expression)
            except RuntimeError:
                v = None
            if v:
                return v
            time.sleep(0.05)
        raise TimeoutError(f"the page never showed {what or expression}")

    def key(self, key: str, code: str, keycode: int) -> None:
        """One key press (down and up) on the focused element."""
        for kind in ("keyDown", "keyUp"):
            self.call("Input.dispatchKeyEvent", type=kind, key=key, code=code,
                      windowsVirtualKeyCode=keycode, nativeVirtualKeyCode=keycode)

    def type_into(self, selector: str, text: str) -> None:
        """Replace an input's text as a user would: select all, then type."""
        self.js(f"(() => {{ const e = document.querySelector({json.dumps(selector)}); e.focus(); e.select(); }})()")
        self.call("Input.insertText", text=text)

    def screenshot(self, path: str | Path) -> Path:
        data = self.call("Page.captureScreenshot", format="png")["data"]
        path = Path(path)
        path.write_bytes(base64.b64decode(data))
        return path

    def close(self) -> None:
        try:
            self.ws.close()
        except Exception:
            pass
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def free_port() -> int:
    """A TCP port free on this machine now."""
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class ExplorerProcess:
    """`taxel explore SCENE --port P --out DIR [extra...]` in a subprocess (after `prefix`, e.g.
    strace); ready when it prints
    its address (the first solve has then been started, not finished); `url` is that address,
    with its token; `log` its output lines (stdout and stderr), read on in a thread."""

    def __init__(self, scene: str, out: str | Path, limit: float = 180.0, *extra: str, cwd: str | Path | None = None,
                 prefix: tuple[str, ...] = (), env: dict | None = None):
        import sys
        import threading
        self.port = free_port()
        env = {**os.environ, "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", **(env or {})}
        self.proc = subprocess.Popen([*prefix, sys.executable, "-m", "taxel.cli", "explore", scene, "--port",
                                      str(self.port), "--out", str(out), *extra],
                                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env, cwd=cwd,
                                     start_new_session=True)     # its own group: close() ends it all
        self.log: list[str] = []
        end = time.monotonic() + limit
        for line in self.proc.stdout:
            self.log.append(line)
            if "taxel explore: serving" in line:
                break
            if time.monotonic() > end:
                break
        else:
            raise RuntimeError("taxel explore exited before serving:\n" + "".join(self.log[-20:]))
        if not self.log or "serving" not in self.log[-1]:
            self.close()
            raise TimeoutError(f"taxel explore did not serve within {limit:.0f} s")
        self.url = self.log[-1].split(" at ", 1)[1].strip()      # with its ?token=...
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:                             # refusals, warnings: kept in `log`
            self.log.append(line)

    def close(self):
        """End the explorer and every process of its group (3D workers; under a `prefix`
        such as strace, the traced explorer too)."""
        import signal
        try:
            os.killpg(self.proc.pid, signal.SIGTERM)
        except ProcessLookupError:
            return
        try:
            self.proc.wait(15)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
