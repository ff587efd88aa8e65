"""What a client may send over the explorer's WebSocket, checked before it costs anything.

trame speaks wslink over one WebSocket per page: msgpack messages cut in chunks,
each chunk's 12-byte header claiming the whole message's size. Left as they are,
an authenticated client could make the server reserve whatever size a header
claims (up to 4 GB), set any state key of every other page (`trame__scripts`
included, whose URLs the page loads), set the server's busy flags, and hold the
event loop with one long value. Here, on the wslink handler of the running server:

- frames: aiohttp refuses a WebSocket frame longer than MAX_MESSAGE from its header,
  before reading it (`max_msg_size`, set through trame's `ws_max_msg_size`); wslink's
  chunk headers may claim at most MAX_MESSAGE, and at most MAX_PENDING messages may be
  half-received per connection (Bounded);
- methods: only those the page calls (METHODS); `trame.state.update`, `trame.state.get`
  and `trame.trigger` go to the explorer with the connection's id (`Explorer.update`,
  `.state_of`, `.trigger`): every page has its own design, nothing a page sends reaches
  another page;
- pace: a connection's messages are taken at most RATE a second (a burst of BURST);
  beyond that its socket is read no faster (back-pressure on that connection only);
- connections: at most MAX_PAGES at once; messages go out one at a time per connection
  (not under wslink's one lock for all), and a page that does not read them within
  SEND_TIMEOUT is closed: a stalled reader holds up no other page;
- every refusal is one line on stderr (Refusals: at most LINES per connection in
  WINDOW seconds, then one line saying how many more), never a traceback.
"""

from __future__ import annotations

import asyncio
import sys
import time
from dataclasses import dataclass, field

import msgpack
from aiohttp import WSMsgType
from wslink.chunking import UnChunker, generate_chunks

MAX_MESSAGE = 2 * 1024 * 1024      # bytes: the largest message a page may send (its largest is a few kB)
MAX_PENDING = 4                    # messages half-received at once, per connection
MAX_PAGES = 32                     # connections at once
RATE, BURST = 500.0, 500           # messages a second per connection, and its burst
LINES, WINDOW = 20, 10.0           # refusal lines per connection per window (s)
SEND_TIMEOUT = 5.0                 # s: a page that reads none of a message in this long is closed
METHODS = ("trame.state.get", "trame.state.update", "trame.trigger", "trame.lifecycle.update",
           "trame.error.client")


class Bounded(UnChunker):
    """wslink's un-chunker with a cap on the size a header may claim (also after the
    hello, where wslink lifts it to 4 GB) and on the messages pending at once."""

    def __init__(self):
        super().__init__()

    def set_max_message_size(self, size):
        super().set_max_message_size(min(size, MAX_MESSAGE))

    def process_chunk(self, chunk: bytes):
        if len(chunk) < 12:
            raise ValueError(f"a chunk of {len(chunk)} bytes, shorter than its 12-byte header")
        if len(self.pending_messages) >= MAX_PENDING and int.from_bytes(chunk[:4], "little") \
                not in self.pending_messages:
            raise ValueError(f"more than {MAX_PENDING} messages half-sent at once")
        return super().process_chunk(chunk)


@dataclass
class Refusals:
    """One line per refusal on stderr, at most LINES per connection per WINDOW s."""

    out: object = None                         # callable(str); default: stderr
    seen: dict = field(default_factory=dict)   # client -> [window start, lines, held back]

    def __call__(self, client: str, what: str) -> None:
        now = time.monotonic()
        w = self.seen.setdefault(client, [now, 0, 0])
        if now - w[0] > WINDOW:
            if w[2]:
                self._line(f"taxel explore: refused {w[2]} more from connection {client[:8]} (not shown)")
            w[:] = [now, 0, 0]
        if w[1] < LINES:
            w[1] += 1
            self._line(f"taxel explore: refused from connection {client[:8]}: {what}")
        else:
            w[2] += 1

    def _line(self, text: str) -> None:
        text = " ".join(text.split())[:300]
        (self.out or (lambda s: print(s, file=sys.stderr, flush=True)))(text)


class Wire:
    """The checks above, installed on a running wslink server (trame's on_server_bind)."""

    def __init__(self, explorer, refusals: Refusals | None = None):
        self.explorer = explorer
        self.refuse = refusals or Refusals()
        self.pace: dict[str, list[float]] = {}
        self.locks: dict[int, asyncio.Lock] = {}

    def install(self, wslink_server) -> None:
        import wslink.protocol
        wslink.protocol.MAX_MSG_SIZE = MAX_MESSAGE       # the chunk size the hello tells the page to send
        for handler in wslink_server._ws_handlers:
            self._wrap(handler)

    def _wrap(self, h) -> None:
        on_connect, on_message, on_close, on_complete = h.onConnect, h.onMessage, h.onClose, h.onCompleteMessage

        async def connect(request, client_id):
            await on_connect(request, client_id)
            h.unchunkers[client_id] = Bounded()
            if len(h.connections) > MAX_PAGES:
                self.refuse(client_id, f"more than {MAX_PAGES} pages connected at once")
                await h.connections[client_id].close(message=b"too many pages")

        async def message(is_binary, msg, client_id):
            if msg.type == WSMsgType.ERROR:          # aiohttp: a frame over max_msg_size, or malformed
                self.refuse(client_id, f"a WebSocket frame: {msg.data}")
                return
            if msg.type != WSMsgType.BINARY:
                if msg.type == WSMsgType.TEXT:
                    self.refuse(client_id, "a text frame (wslink speaks binary frames)")
                return
            await self._pace(client_id)
            try:
                await on_message(is_binary, msg, client_id)
            except Exception as exc:                 # a malformed chunk or message: refused, connection closed
                self.refuse(client_id, f"a malformed message ({type(exc).__name__}: {str(exc)[:120]}); "
                                       "connection closed")
                ws = h.connections.get(client_id)
                if ws is not None:
                    await ws.close(message=b"malformed message")

        async def close(client_id):
            self.pace.pop(client_id, None)
            self.locks.pop(id(h.connections.get(client_id)), None)
            self.refuse.seen.pop(client_id, None)
            self.explorer.closed(client_id)
            await on_close(client_id)

        async def complete(rpc, client_id):
            if not isinstance(rpc, dict) or not isinstance(rpc.get("id"), str) \
                    or not isinstance(rpc.get("method"), str):
                self.refuse(client_id, "a message that is not a wslink call")
                return
            if rpc["id"].startswith("system:") or not h.isClientAuthenticated(client_id):
                return await on_complete(rpc, client_id)          # the hello, or wslink's own refusal
            method, args = rpc["method"], rpc.get("args") if isinstance(rpc.get("args"), list) else []
            if method not in METHODS:
                self.refuse(client_id, f"the method {method[:60]!r}")
                return await h.sendWrappedError(rpc["id"], -32601, "refused method", client_id=client_id)
            try:
                result = self._call(client_id, method, args)
            except Exception as exc:                 # a bug or the disk: one line, the connection goes on
                self.refuse(client_id, f"{method} failed ({type(exc).__name__}: {str(exc)[:120]})")
                return await h.sendWrappedError(rpc["id"], -32000, "failed", client_id=client_id)
            if client_id in h.connections and not h.connections[client_id].closed:
                await h.sendWrappedMessage(rpc["id"], result, method=method, client_id=client_id)

        async def send(rpcid, content, method="", client_id=None, skip_last_active_client=False):
            sockets = h.getAuthenticatedWebsockets(client_id, skip_last_active_client)
            await self._send(h, {"wslink": "1.0", "id": rpcid, "result": content}, sockets)

        async def send_error(rpcid, code, message, data=None, client_id=None):   # never a traceback sent
            sockets = [h.connections.get(client_id)] if client_id else list(h.connections.values())
            await self._send(h, {"wslink": "1.0", "id": rpcid, "error": {"code": code, "message": message}},
                             sockets)

        h.onConnect, h.onMessage, h.onClose, h.onCompleteMessage = connect, message, close, complete
        h.sendWrappedMessage, h.sendWrappedError = send, send_error
        self.explorer.publish = lambda client_id, data: h.publish("trame.state.topic", data, client_id=client_id)

    async def _send(self, h, wrapper: dict, sockets: list) -> None:
        """A message to each socket: one send at a time per socket (aiohttp's rule), not one
        for all (wslink's lock); a socket whose page does not read within SEND_TIMEOUT is
        closed, so it holds up no one else."""
        try:
            packed = msgpack.packb(wrapper)
        except Exception:
            packed = msgpack.packb({"wslink": "1.0", "id": wrapper["id"],
                                    "error": {"code": -32002, "message": "result not serializable"}})
        for ws in sockets:
            if ws is None or ws.closed:
                continue
            lock = self.locks.setdefault(id(ws), asyncio.Lock())
            try:
                async with lock:
                    await asyncio.wait_for(self._chunks(ws, packed), SEND_TIMEOUT)
            except TimeoutError:
                client = next((c for c, w in h.connections.items() if w is ws), "?")
                self.refuse(client, f"a page that does not read its messages ({SEND_TIMEOUT:g} s); connection closed")
                transport = getattr(getattr(ws, "_writer", None), "transport", None)
                if transport is not None:
                    transport.abort()
            except (ConnectionError, RuntimeError):     # the page left meanwhile
                pass

    @staticmethod
    async def _chunks(ws, packed: bytes) -> None:
        import wslink.protocol
        for chunk in generate_chunks(packed, wslink.protocol.MAX_MSG_SIZE):
            await ws.send_bytes(chunk)

    def _call(self, client_id: str, method: str, args: list):
        ex = self.explorer
        if method == "trame.state.get":
            return ex.state_of(client_id)
        if method == "trame.state.update":
            changes = args[0] if args else None
            if not isinstance(changes, list) or not all(isinstance(c, dict) for c in changes):
                self.refuse(client_id, "trame.state.update without a list of changes")
                return None
            ex.update(client_id, changes)
            return None
        if method == "trame.trigger":
            name = args[0] if args else None
            targs = args[1] if len(args) > 1 and isinstance(args[1], list) else []
            ex.trigger(client_id, name, targs)
            return None
        if method == "trame.error.client":
            self.refuse(client_id, f"(a script error in the page) {str(args[0] if args else '')[:200]}")
        return None                                  # trame.lifecycle.update: nothing of the server's is run

    async def _pace(self, client_id: str) -> None:
        """A token bucket per connection: beyond RATE, its messages wait (this connection only)."""
        now = time.monotonic()
        b = self.pace.setdefault(client_id, [float(BURST), now, 0.0])
        b[0] = min(BURST, b[0] + (now - b[1]) * RATE)
        b[1] = now
        if b[0] < 1:
            wait = (1 - b[0]) / RATE
            if now - b[2] > WINDOW:
                b[2] = now
                self.refuse(client_id, f"more than {RATE:g} messages a second: read slower")
            await asyncio.sleep(wait)
            b[0], b[1] = 1.0, time.monotonic()
        b[0] -= 1
