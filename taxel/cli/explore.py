"""`taxel explore [SCENE | FOLDER] [--port P] [--host H] [--out DIR] [--no-token]`: the design explorer.

Serves a web page of sliders over the scene's design variables and prints its
address, with a random token in it (as Jupyter does): the page and its WebSocket
need it, and every request's Host and Origin are checked (taxel.explore.guard).
It binds to this machine (127.0.0.1) unless --host says otherwise; then it says
so. --no-token only on 127.0.0.1. Every value is still checked against the scene
schema, and saved scenes only go under --out.
"""

from __future__ import annotations

import socket
import sys

from taxel.cli.files import InputError, number


def register(sub) -> None:
    p = sub.add_parser("explore", help="a web page of sliders over a design (live 2D/axisymmetric answers)")
    p.add_argument("scene", nargs="?", default="thesis-pzt-single-2d",
                   help="scene file, built-in name, or a result/study/optimization folder (default: %(default)s)")
    p.add_argument("--port", type=number(1, 65535, integer=True), default=8080, help="port (default %(default)s)")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to bind (default 127.0.0.1: this machine only; 0.0.0.0: the network)")
    p.add_argument("--no-token", action="store_true",
                   help="no token in the address (only with --host 127.0.0.1: every local user and program "
                        "can then drive it)")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="the explorer's store and saved scenes (default out/explore/NAME)")
    p.set_defaults(run=_explore)


def _explore(args):
    from taxel import api
    if args.no_token and args.host not in ("127.0.0.1", "localhost", "::1"):
        raise InputError(f"--no-token with --host {args.host}: anyone who can reach the port could drive the "
                         "explorer; keep the token, or bind --host 127.0.0.1")
    try:
        with socket.socket(socket.AF_INET6 if ":" in args.host else socket.AF_INET) as s:
            s.bind((args.host, args.port))
    except OSError as exc:
        raise InputError(f"--host {args.host} --port {args.port}: cannot bind ({exc.strerror or exc}); "
                         "choose another --port or a local --host") from None
    if args.host not in ("127.0.0.1", "localhost", "::1"):
        print(f"taxel explore: listening on {args.host}:{args.port}, reachable from other machines; "
              "only with the token in the printed address", file=sys.stderr, flush=True)
    api.serve_explorer(args.scene, args.out, host=args.host, port=args.port, token=not args.no_token)
