"""Who may reach the explorer: a token, and the Host and Origin of every request.

The explorer is a web server that solves designs and writes files under its output
folder; whoever reaches its port drives it. As Jupyter's server does, every HTTP
request and the WebSocket are checked (an aiohttp middleware on trame's wslink app):

- the token: a random 32-byte URL-safe string (`secrets.token_urlsafe`), printed in
  the page's address (`?token=...`). A request carrying it in its query sets a cookie
  (HttpOnly, SameSite=Strict) that the page's later requests and its WebSocket carry;
  a request with neither is refused. A browser sends a cookie of 127.0.0.1 to every
  port of 127.0.0.1, so the cookie is named after this port and holds an HMAC of the
  token (`cookie_value`), never the token: a listener on another port learns neither
  the token nor another explorer's cookie. `token=None` (--no-token) is allowed only
  on a loopback address (checked by the caller, `check_bind`);
- the wslink secret (the WebSocket's hello): a new one each run (from the token, or
  random with --no-token), never wslink's public default; the page learns it from
  the redirect of its first request (`?secret=`, which trame's page reads and drops
  from the address);
- the Host header, on every bind: on a loopback bind only 127.0.0.1, localhost or
  [::1] at this port (DNS rebinding: a foreign name resolved to 127.0.0.1 still says
  its own Host); on another bind also this machine's names and addresses;
- the Origin header, when there is one (browsers send it on every WebSocket and on
  cross-site requests): it must be this server's own origin, the Host asked for.
  A page on another site cannot open the explorer's WebSocket.

Each refusal is answered 403 and logged in one line on stderr.
"""

from __future__ import annotations

import hmac
import secrets
import socket
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

    secret: str = field(default="", repr=False)

    def __post_init__(self):
        self.secret = self.secret or (hmac.new(self.token.encode(), b"wslink secret", "sha256").hexdigest()
                                      if self.token else secrets.token_urlsafe(32))
        self._hosts = self._allowed_hosts()

    @property
    def cookie(self) -> str:
        return f"taxel-explore-{self.port}"

    def cookie_value(self) -> str:
        """The cookie's value: an HMAC of the token and this port (not the token)."""
        return hmac.new(self.token.encode(), f"cookie {self.port}".encode(), "sha256").hexdigest()

    def _allowed_hosts(self) -> set[str]:
        names = {"127.0.0.1", "localhost", "[::1]"}
        if self.host not in LOOPBACK:
            names |= {socket.gethostname().lower(), socket.getfqdn().lower()}
            if self.host not in ("0.0.0.0", "::"):
                names.add(f"[{self.host}]" if ":" in self.host else self.host)
            else:
                names |= {f"[{a}]" if ":" in a else a for a in _addresses()}
        return {f"{h}:{self.port}" for h in names}

    def hosts(self) -> set[str]:
        """The Host headers accepted (host:port)."""
        return self._hosts

    def url(self, path: str = "/") -> str:
        host = "127.0.0.1" if self.host in ("0.0.0.0", "::") else self.host
        host = f"[{host}]" if ":" in host else host
        return f"http://{host}:{self.port}{path}" + (f"?token={self.token}" if self.token else "")

    def why_refused(self, request: web.BaseRequest) -> str | None:
        """Why this request may not in, or None."""
        host = request.headers.get("Host", "")
        if host.lower() not in self.hosts():
            return f"Host {host!r} is not this server (DNS rebinding?)"
        origin = request.headers.get("Origin")
        if origin is not None and urlsplit(origin).netloc.lower() != host.lower():
            return f"Origin {origin!r} is not this page's ({host})"
        if self.token is not None:
            query, cookie = request.query.get("token", ""), request.cookies.get(self.cookie, "")
            if not (hmac.compare_digest(query.encode(), self.token.encode())
                    or hmac.compare_digest(cookie.encode(), self.cookie_value().encode())):
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
            if request.method == "GET" and request.path in ("/", "/index.html") and "secret" not in request.query:
                # the page's first request: to the same page with this run's wslink secret (trame's
                # page reads it from its address and drops it), the token traded for the cookie
                response = web.Response(status=302, headers={"Location": f"{request.path}?secret={self.secret}"})
            else:
                response = await handler(request)
            if self.token is not None and request.query.get("token") == self.token and \
                    isinstance(response, web.StreamResponse) and not response.prepared:
                response.set_cookie(self.cookie, self.cookie_value(), httponly=True, samesite="Strict", path="/")
            return response
        return guard


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _addresses() -> set[str]:
    """This machine's IP addresses (a bind on every interface answers on each)."""
    found = set()
    try:
        for info in socket.getaddrinfo(socket.gethostname(), None):
            found.add(info[4][0].split("%")[0])
    except OSError:
        pass
    try:
        import psutil
        for addrs in psutil.net_if_addrs().values():
            found |= {a.address.split("%")[0] for a in addrs if a.family in (socket.AF_INET, socket.AF_INET6)}
    except ImportError:
        pass
    return found


TLS_ADVICE = ("the explorer serves plain HTTP: the token and every value cross the network readable by "
              "anyone on the path; keep --host 127.0.0.1 and reach it through an SSH tunnel "
              "(ssh -L PORT:127.0.0.1:PORT this-machine), or put it behind a TLS reverse proxy "
              "(Caddy, nginx) that forwards to 127.0.0.1:PORT with that Host header")
