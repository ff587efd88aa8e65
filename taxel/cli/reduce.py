"""`taxel reduce SCENE -o FILE`: the scene's reduced model, exported.

    taxel reduce SCENE -o FILE [--inputs taxels|probe] [--output readout|charge] [--f-max HZ]

FILE by its suffix: `.npz` (the project's file: state space, reduced model and
provenance), `.mat` (MATLAB/Simulink: A, B, C, D, names, units), or a folder
(result.json, scene.json, model.npz, model.mat; read back by taxel.read).
Bad input: one line, exit 2.
"""

from __future__ import annotations

from pathlib import Path

from taxel.cli.files import number


def register(sub) -> None:
    p = sub.add_parser("reduce", help="a reduced-order state-space model of a scene (.npz, .mat or a folder)")
    p.add_argument("scene", help="scene TOML file or built-in example name")
    p.add_argument("-o", "--out", required=True, metavar="FILE", help="FILE.npz, FILE.mat or a folder")
    p.add_argument("--inputs", choices=["taxels", "probe"], default=None,
                   help="a force on each taxel (array scenes, the default) or the scene's own load")
    p.add_argument("--output", choices=["readout", "charge"], default="readout",
                   help="the scene's readout chain (default) or the short-circuit charges")
    p.add_argument("--f-max", type=number(0, 1e9, low_open=True, unit="Hz"), default=None, metavar="HZ",
                   help="highest frequency the model must hold (default: the scene's, at least 2000)")
    p.set_defaults(run=_reduce)


def _reduce(args):
    from taxel import api
    out = Path(args.out)
    if out.suffix not in ("", ".npz", ".mat"):
        raise ValueError(f"-o {out}: use FILE.npz, FILE.mat or a folder name (no suffix)")
    model = api.reduce(args.scene, inputs=args.inputs, output=args.output, f_max=args.f_max)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"-o {out}: cannot create its folder ({exc.strerror or exc})") from None
    if out.suffix == ".npz":
        written = [model.save(out)]
    elif out.suffix == ".mat":
        written = [model.save_mat(out)]
    else:
        written = model.to_folder(out)
    print("\n".join(model.summary()))
    print("wrote " + ", ".join(str(p) for p in written))
