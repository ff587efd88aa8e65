"""A minimal wslink client: the protocol trame's page speaks over its WebSocket.

msgpack messages in wslink's chunks (wslink.chunking, the library's own framing), over
websocket-client. Used by the tests and benchmarks that talk to `taxel explore` as a
page, or a crafted program, would (tests/test_explore_guard.py, test_explore_attack.py,
benchmarks/explore_load.py).
"""

from __future__ import annotations

import itertools
import urllib.error
import urllib.request

import msgpack
import websocket
from wslink.chunking import UnChunker, generate_chunks


class HandshakeRefused(Exception):
    """The server answered the WebSocket upgrade with an HTTP error (`status`)."""

    def __init__(self, status: int):
        super().__init__(f"HTTP {status}")
        self.status = status


class Client:
    """One WebSocket connection to a trame server's /ws."""

    def __init__(self, url: str, origin: str | None = None, host: str | None = None, timeout: float = 120.0,
                 secret: str = "wslink-secret"):
        try:
            self.ws = websocket.create_connection(url, origin=origin, host=host, timeout=timeout,
                                                  suppress_origin=origin is None)
        except websocket.WebSocketBadStatusException as exc:
            raise HandshakeRefused(exc.status_code) from None
        self.ids = itertools.count(1)
        self.unchunker = UnChunker()
        self.unchunker.set_max_message_size(1 << 30)
        self.client = "c0"
        self.secret = secret

    @classmethod
    def of(cls, url: str, timeout: float = 120.0) -> Client:
        """A client of the explorer at its printed address (with the token), said hello to."""
        base, token = url.split("?token=")
        host = base.split("//", 1)[1].rstrip("/")
        c = cls(f"ws://{host}/ws?token={token}", origin=f"http://{host}", timeout=timeout, secret=page_secret(url))
        c.hello()
        return c

    def send(self, method: str, *args, id: str | None = None) -> str:
        rpc = id or f"rpc:{self.client}:{next(self.ids)}"
        packed = msgpack.packb({"wslink": "1.0", "id": rpc, "method": method, "args": list(args), "kwargs": {}})
        for chunk in generate_chunks(packed, 512 * 1024):
            self.ws.send_binary(chunk)
        return rpc

    def next(self) -> dict | None:
        """The next whole message received (None: a chunk of one not yet whole)."""
        frame = self.ws.recv()
        if isinstance(frame, str):
            return None
        msg = self.unchunker.process_chunk(frame)
        if msg is None:
            return None
        return msg if isinstance(msg, dict) else msgpack.unpackb(msg, strict_map_key=False)

    def receive(self, rpc: str) -> dict:
        """The reply to `rpc` (messages pushed meanwhile are skipped)."""
        while True:
            data = self.next()
            if data is not None and data.get("id") == rpc:
                return data

    def call(self, method: str, *args) -> dict:
        return self.receive(self.send(method, *args))

    def hello(self, secret: str | None = None) -> dict:
        reply = self.receive(self.send("wslink.hello", {"secret": secret or self.secret}, id="system:c0:0"))
        self.client = reply.get("result", {}).get("clientID", "c0")
        return reply

    def close(self) -> None:
        self.ws.close()


def page_secret(url: str, timeout: float = 120.0) -> str:
    """The wslink secret of an explorer's run, as its page learns it: the `?secret=` of the
    redirect answering the printed address (with its token)."""

    class Stop(urllib.request.HTTPRedirectHandler):
        def redirect_request(self, *a, **k):
            return None
    try:
        urllib.request.build_opener(Stop).open(url, timeout=timeout)
    except urllib.error.HTTPError as exc:
        if exc.code == 302:
            return exc.headers["Location"].split("secret=", 1)[1]
        raise
    raise RuntimeError(f"{url}: no redirect with the page's secret")
