"""`taxel explore [SCENE | FOLDER] [--port P] [--host H] [--out DIR]`: the design explorer.

Serves a web page of sliders over the scene's design variables and prints its
address. It binds to this machine (127.0.0.1) unless --host says otherwise; then
it says so, because anyone who can reach the port can solve designs (every value
is still checked against the scene schema, and saved scenes only go under --out).
"""

from __future__ import annotations

import socket
import sys

from taxel.cli.files import InputError


def register(sub) -> None:
    p = sub.add_parser("explore", help="a web page of sliders over a design (live 2D/axisymmetric answers)")
    p.add_argument("scene", nargs="?", default="thesis-pzt-single-2d",
                   help="scene file, built-in name, or a result/study/optimization folder (default: %(default)s)")
    p.add_argument("--port", type=int, default=8080, help="port (default %(default)s)")
    p.add_argument("--host", default="127.0.0.1",
                   help="address to bind (default 127.0.0.1: this machine only; 0.0.0.0: the network)")
    p.add_argument("--out", default=None, metavar="DIR",
                   help="the explorer's store and saved scenes (default out/explore/NAME)")
    p.set_defaults(run=_explore)


def _explore(args):
    from taxel import api
    if not 0 < args.port < 65536:
        raise InputError(f"--port {args.port}: give a port between 1 and 65535")
    try:
        with socket.socket(socket.AF_INET6 if ":" in args.host else socket.AF_INET) as s:
            s.bind((args.host, args.port))
    except OSError as exc:
        raise InputError(f"--host {args.host} --port {args.port}: cannot bind ({exc.strerror or exc}); "
                         "choose another --port or a local --host") from None
    if args.host not in ("127.0.0.1", "localhost", "::1"):
        print(f"taxel explore: listening on {args.host}:{args.port}, reachable from other machines; "
              "values outside the scene schema are refused", file=sys.stderr, flush=True)
    api.explore(args.scene, args.out, host=args.host, port=args.port)
