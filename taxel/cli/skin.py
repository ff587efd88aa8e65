"""`taxel skin SCENE -o FILE.npz`: the scene's skin for a robot simulator.

    taxel skin SCENE -o FILE.npz [--dt S] [--per-pitch N] [--checks N] [--rig RIG]

Writes the skin file (taxel.skin.model: layout, influence with its measured
interpolation error, the readout dynamics discretized at --dt, noise, saturation,
provenance) that taxel.skin.runtime.SkinRuntime runs at each simulator step.
Bad input: one line, exit 2, nothing written.
"""

from __future__ import annotations

from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("skin", help="a skin file for a robot simulator (taxel voltages from contact forces)")
    p.add_argument("scene", help="scene TOML file or built-in example name (a square taxel array)")
    p.add_argument("-o", "--out", required=True, metavar="FILE", help="FILE.npz")
    p.add_argument("--dt", type=float, default=1e-3, metavar="S", help="the simulator's step, s (default 0.001)")
    p.add_argument("--per-pitch", type=int, default=8, metavar="N", help="FEM presses per pitch (default 8)")
    p.add_argument("--checks", type=int, default=4, metavar="N",
                   help="FEM presses between the knots that measure the influence's interpolation error (default 4)")
    p.add_argument("--rig", default=None, metavar="RIG", help="a bench rig (name or TOML): its ADC and conditioning")
    p.set_defaults(run=_skin)


def _skin(args):
    from taxel import api
    out = Path(args.out)
    if out.suffix != ".npz":
        raise ValueError(f"-o {out}: use FILE.npz")
    if not out.parent.is_dir():
        raise ValueError(f"-o {out}: folder {out.parent} does not exist; create it first")
    model = api.skin(args.scene, None, args.dt, args.per_pitch, args.checks, args.rig)
    model.save(out)
    print(f"skin of {model.provenance['scene_name']}: {model.rows} x {model.cols} taxels, pitch "
          f"{1e3 * model.pitch:g} mm, {model.Ad.shape[0]} states at dt {model.dt:g} s, {model.readout}")
    print(f"  influence: {len(model.knots)} knots, interpolation error {model.influence_error:.1e} of G's peak "
          f"at {len(model.check_x)} FEM presses between knots; dynamics error {model.reduction_error:.1e}")
    print(f"wrote {out}")
