"""The simulator's side of the wire: byte corruption, and playing a byte stream
into a pseudo-terminal, a loopback TCP port or a file, paced at the frame rate.

A pty is a real serial port to pyserial (open its slave path); a loopback port
is `socket://127.0.0.1:PORT`. Both end (the master or the connection closed)
after the stream and `linger` seconds, which a capture sees as a vanished port.
"""

from __future__ import annotations

import os
import socket
import threading
import time
import tty
from dataclasses import dataclass

import numpy as np


CONNECT_SETTLE = 0.3      # s between a client's connection and the first byte


@dataclass
class Wire:
    """A byte stream and where each frame ends in it (after corruption)."""

    data: bytes
    ends: np.ndarray              # (N,) end offset of each frame's bytes
    intact: np.ndarray            # (N,) bool: this frame and the delimiter before it are untouched
    flips: int = 0
    drops: int = 0


def assemble(chunks: list[bytes]) -> Wire:
    ends = np.cumsum([len(c) for c in chunks])
    return Wire(b"".join(chunks), ends, np.ones(len(chunks), bool))


def corrupt(chunks: list[bytes], p: float, rng: np.random.Generator) -> Wire:
    """Each byte flipped (XOR a random non-zero mask) with probability p/2 or dropped
    with probability p/2. A frame counts as intact if none of its bytes and not the
    delimiter ending the frame before it was touched: exactly the frames a correct
    decoder must recover."""
    if p <= 0:
        return assemble(chunks)
    lens = np.array([len(c) for c in chunks])
    buf = np.frombuffer(b"".join(chunks), np.uint8).copy()
    owner = np.repeat(np.arange(len(chunks)), lens)
    u = rng.random(len(buf))
    flip, drop = u < p / 2, (u >= p / 2) & (u < p)
    buf[flip] ^= rng.integers(1, 256, int(flip.sum()), dtype=np.uint8)
    hit = np.zeros(len(chunks), bool)
    hit[owner[flip | drop]] = True
    ends = np.cumsum(lens) - 1
    delim_hit = (flip | drop)[ends]                 # the last byte of each frame is its delimiter
    intact = ~hit
    intact[1:] &= ~delim_hit[:-1]
    keep = ~drop
    new_ends = np.cumsum(np.bincount(owner[keep], minlength=len(chunks)))
    return Wire(buf[keep].tobytes(), new_ends, intact, int(flip.sum()), int(drop.sum()))


def play(write, wire: Wire, rate: float | None, stop: threading.Event, tick: float = 0.01) -> int:
    """Write the stream through `write(bytes)`, frame k due at k / rate (all at once
    if rate is None). Returns the bytes written."""
    if rate is None:
        write(wire.data)
        return len(wire.data)
    t0, sent, k, n = time.monotonic(), 0, 0, len(wire.ends)
    while k < n and not stop.is_set():
        due = min(n, int((time.monotonic() - t0) * rate) + 1)
        if due > k:
            end = int(wire.ends[due - 1])
            write(wire.data[sent:end])
            sent, k = end, due
        time.sleep(tick)
    return sent


class Player:
    """Plays a Wire in a thread, into a pty (`Player.pty`) or a loopback TCP port
    (`Player.tcp`). `url` is what the capture opens; `stop()` ends it early;
    `join()` waits. Used as a context manager, it is always stopped."""

    def __init__(self, wire: Wire, rate: float | None, linger: float = 1.0, delay: float = 0.0):
        self.wire, self.rate, self.linger, self.delay = wire, rate, linger, delay
        self.url = ""
        self.stop_event, self.done = threading.Event(), threading.Event()
        self.sent, self.error = 0, None
        self._thread = None

    @classmethod
    def pty(cls, wire: Wire, rate: float | None, linger: float = 1.0, start: bool = True,
            delay: float = 0.0) -> Player:
        """A pty player. pyserial empties the input buffer when it opens a port, so
        bytes sent before the capture opened it are lost, as on a real serial line:
        with start=False the stream begins at `start()` (open the port first)."""
        self = cls(wire, rate, linger, delay)
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)                    # no echo, no newline translation
        self.url = os.ttyname(self._slave)
        self._thread = threading.Thread(target=self._run_pty, daemon=True)
        if start:
            self.start()
        return self

    def start(self):
        if not self._thread.is_alive() and not self.done.is_set():
            self._thread.start()

    @classmethod
    def tcp(cls, wire: Wire, rate: float | None, port: int = 0, linger: float = 1.0) -> Player:
        self = cls(wire, rate, linger)
        self._server = socket.create_server(("127.0.0.1", port))
        self._server.settimeout(0.1)
        self.url = f"socket://127.0.0.1:{self._server.getsockname()[1]}"
        self._thread = threading.Thread(target=self._run_tcp, daemon=True)
        self._thread.start()
        return self

    def _finish(self):
        end = time.monotonic() + self.linger
        while time.monotonic() < end and not self.stop_event.is_set():
            time.sleep(0.02)

    def _run_pty(self):
        def write(b):
            view = memoryview(b)
            while view:
                view = view[os.write(self._master, view):]
        try:
            self.stop_event.wait(self.delay)
            self.sent = play(write, self.wire, self.rate, self.stop_event)
            self._finish()
        except OSError as exc:
            self.error = exc
        finally:
            os.close(self._master)                 # the reader's port vanishes here
            os.close(self._slave)
            self.done.set()

    def _run_tcp(self):
        conn = None
        try:
            while conn is None and not self.stop_event.is_set():
                try:
                    conn, _ = self._server.accept()
                except socket.timeout:
                    continue
            if conn is not None:
                conn.setblocking(True)
                # pyserial's open empties the input buffer after it connects: start a moment later
                self.stop_event.wait(CONNECT_SETTLE)
                def send(b):                       # MSG_NOSIGNAL: a reader that went away is an
                    view = memoryview(b)           # error here, never a SIGPIPE for the whole process
                    while view:
                        view = view[conn.send(view, socket.MSG_NOSIGNAL):]
                self.sent = play(send, self.wire, self.rate, self.stop_event)
                self._finish()
        except OSError as exc:
            self.error = exc
        finally:
            if conn is not None:
                conn.close()
            self._server.close()
            self.done.set()

    def stop(self):
        self.stop_event.set()
        if self._thread is not None and not self._thread.is_alive() and not self.done.is_set():
            self._thread.start()                   # never started: run it to close the pty
        self.join()

    def join(self, timeout: float | None = None):
        if self._thread is not None and self._thread.is_alive():
            self._thread.join(timeout)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()
