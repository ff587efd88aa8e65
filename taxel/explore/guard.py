"""Who may reach the explorer: a token, and the Host and Origin of every request.

The explorer is a web server that solves designs and writes files under its output
folder; whoever reaches its port drives it. As Jupyter's server does, every HTTP
request and the WebSocket are checked (an aiohttp middleware on trame's wslink app):

- the token: a random 32-byte URL-safe string (`secrets.token_urlsafe`), printed in
  the page's address (`?token=...`). A request carrying it in its query sets a cookie
  (HttpOnly, SameSite=Strict, named after the port) that the page's later requests
  and its WebSocket carry; a request with neither is refused. `token=None` (--no-token)
  is allowed only on a loopback address (checked by the caller, `check_bind`);
- the Host header, on a loopback bind: only 127.0.0.1, localhost or [::1] at this
  port (DNS rebinding: a foreign name resolved to 127.0.0.1 still says its own Host);
- the Origin header, when there is one (browsers send it on every WebSocket and on
  cross-site requests): it must be this server's own origin, the Host asked for.
  A page on another site cannot open the explorer's WebSocket.

Each refusal is answered 403 and logged in one line on stderr.
"""

from __future__ import annotations

import hmac
import secrets
import sys
from dataclasses import dataclass, field
from urllib.parse import urlsplit

from aiohttp import web

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def new_token() -> str:
    """A fresh random token (256 bits)."""
    return secrets.token_urlsafe(32)


def check_bind(host: str, token: str | None) -> None:
    """--no-token only on this machine: ValueError (one line) otherwise."""
    if token is None and host not in LOOPBACK:
        raise ValueError(f"--no-token with --host {host}: anyone who can reach the port could drive the "
                         "explorer; keep the token, or bind --host 127.0.0.1")


@dataclass
class Guard:
    """The checks of one explorer server bound to `host`:`port`."""

    host: str
    port: int
    token: str | None
    log: object = field(default=None, repr=False)      # callable(str); default: a line on stderr
    refused: int = 0

    @property
    def cookie(self) -> str:
        return f"taxel-explore-{self.port}"

    def hosts(self) -> set[str] | None:
        """The Host headers accepted (None: any, a bind beyond this machine; the token guards it)."""
        if self.host not in LOOPBACK:
            return None
        return {f"{h}:{self.port}" for h in ("127.0.0.1", "localhost", "[::1]")}

    def url(self, path: str = "/") -> str:
        host = "127.0.0.1" if self.host in ("0.0.0.0", "::") else self.host
        host = f"[{host}]" if ":" in host else host
        return f"http://{host}:{self.port}{path}" + (f"?token={self.token}" if self.token else "")

    def why_refused(self, request: web.BaseRequest) -> str | None:
        """Why this request may not in, or None."""
        host = request.headers.get("Host", "")
        allowed = self.hosts()
        if allowed is not None and host.lower() not in allowed:
            return f"Host {host!r} is not this server (DNS rebinding?)"
        origin = request.headers.get("Origin")
        if origin is not None and urlsplit(origin).netloc.lower() != host.lower():
            return f"Origin {origin!r} is not this page's ({host})"
        if self.token is not None:
            given = request.query.get("token") or request.cookies.get(self.cookie) or ""
            if not hmac.compare_digest(given.encode(), self.token.encode()):
                return "no valid token (open the address taxel explore printed, with its ?token=...)"
        return None

    def middleware(self):
        """The aiohttp middleware: refuse (403, one logged line), else serve; a request
        that shows the token in its query gets the cookie."""
        @web.middleware
        async def guard(request: web.Request, handler):
            why = self.why_refused(request)
            if why is not None:
                self.refused += 1
                (self.log or _stderr)(f"taxel explore: refused {request.method} {request.path} from "
                                      f"{request.remote}: {why}")
                return web.Response(status=403, text=f"taxel explore: refused: {why}\n")
            response = await handler(request)
            if self.token is not None and request.query.get("token") == self.token and \
                    isinstance(response, web.StreamResponse) and not response.prepared:
                response.set_cookie(self.cookie, self.token, httponly=True, samesite="Strict", path="/")
            return response
        return guard


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)
