"""`taxel skin SCENE -o FILE.npz`: the scene's skin for a robot simulator.

    taxel skin SCENE -o FILE.npz [--dt S] [--per-pitch N] [--checks N] [--rig RIG]
    taxel skin dataset SKIN.npz -o FILE.h5 [--presses N] [--seed N] [--duration S] [--no-noise]

Writes the skin file (taxel.skin.model: layout, influence with its measured
interpolation error, the readout dynamics discretized at --dt, noise, saturation,
provenance) that taxel.skin.runtime.SkinRuntime runs at each simulator step.
`taxel skin dataset` runs labelled presses through a skin file into HDF5
(taxel.skin.dataset: the schema) and prints the model-based baseline's scores.
Bad input: one line, exit 2, nothing written.
"""

from __future__ import annotations

from pathlib import Path

from taxel.cli.files import number


def register(sub) -> None:
    p = sub.add_parser("skin", help="a skin file for a robot simulator (taxel voltages from contact forces)")
    p.add_argument("scene", help="scene TOML file or built-in example name (a square taxel array), or 'dataset'")
    p.add_argument("skin", nargs="?", default=None, metavar="SKIN.npz", help="dataset: the skin file to press")
    p.add_argument("-o", "--out", required=True, metavar="FILE", help="FILE.npz (a skin) or FILE.h5 (a dataset)")
    p.add_argument("--dt", type=number(0, 1, low_open=True, unit="s"), default=None, metavar="S", help="the simulator's step, s (default 0.001)")
    p.add_argument("--per-pitch", type=number(2, 16, integer=True), default=None, metavar="N", help="FEM presses per pitch (default 8)")
    p.add_argument("--checks", type=number(0, 16, integer=True), default=None, metavar="N",
                   help="FEM presses between the knots that measure the influence's interpolation error (default 4)")
    p.add_argument("--rig", default=None, metavar="RIG", help="a bench rig (name or TOML): its ADC and conditioning")
    p.add_argument("--presses", type=number(1, 1_000_000, integer=True), default=None, metavar="N", help="dataset: presses (default 200)")
    p.add_argument("--seed", type=number(0, 2**32 - 1, integer=True), default=None, metavar="N", help="dataset: the random seed (default 0)")
    p.add_argument("--duration", type=number(0, 60, low_open=True, unit="s"), default=None, metavar="S", help="dataset: seconds per press (0.3)")
    p.add_argument("--no-noise", action="store_true", default=None, help="dataset: clean voltages")
    p.set_defaults(run=_skin)


BUILD = {"dt": 1e-3, "per_pitch": 8, "checks": 4, "rig": None}
DATASET = {"presses": 200, "seed": 0, "duration": 0.3, "no_noise": False}


def _only(args, given: dict, mode: str) -> None:
    """Refuse the options of the other form; fill this form's defaults."""
    other = DATASET if given is BUILD else BUILD
    wrong = [k for k in other if getattr(args, k) is not None]
    if wrong:
        opt = "--" + wrong[0].replace("_", "-")
        raise ValueError(f"{opt}: not an option of {mode}; see taxel skin --help")
    for k, v in given.items():
        if getattr(args, k) is None:
            setattr(args, k, v)


def _dataset(args):
    from taxel.skin import dataset
    from taxel.skin.model import SkinModel
    _only(args, DATASET, "taxel skin dataset SKIN.npz")
    out = Path(args.out)
    if args.skin is None:
        raise ValueError("taxel skin dataset: give the skin file, taxel skin dataset SKIN.npz -o FILE.h5")
    if out.suffix not in (".h5", ".hdf5"):
        raise ValueError(f"-o {out}: use FILE.h5")
    if not out.parent.is_dir():
        raise ValueError(f"-o {out}: folder {out.parent} does not exist; create it first")
    skin = SkinModel.load(args.skin)
    dataset.write(skin, out, args.presses, args.seed, args.duration, not args.no_noise)
    b = dataset.baseline(dataset.read(out))
    print(f"wrote {out}: {args.presses} presses, seed {args.seed}; baseline ({b['method']}):")
    for k, v in b.items():
        if k != "method":
            print(f"  {k:7s} {v['presses']:4d} presses: position error median {v['position_error_mm_median']:.2f} mm, "
                  f"rms {v['position_error_mm_rms']:.2f} mm; force error median |{v['force_error_pc_median_abs']:.1f}| %")


def _skin(args):
    from taxel import api
    if args.scene == "dataset":
        return _dataset(args)
    if args.skin is not None:
        raise ValueError(f"taxel skin {args.scene} {args.skin}: one scene; a dataset is taxel skin dataset SKIN.npz")
    _only(args, BUILD, "taxel skin SCENE")
    out = Path(args.out)
    if out.suffix != ".npz":
        raise ValueError(f"-o {out}: use FILE.npz")
    if not out.parent.is_dir():
        raise ValueError(f"-o {out}: folder {out.parent} does not exist; create it first")
    model = api.build_skin(args.scene, None, args.dt, args.per_pitch, args.checks, args.rig)
    model.save(out)
    print(f"skin of {model.provenance['scene_name']}: {model.rows} x {model.cols} taxels, pitch "
          f"{1e3 * model.pitch:g} mm, {model.Ad.shape[0]} states at dt {model.dt:g} s, {model.readout}")
    print(f"  influence: {len(model.knots)} knots, interpolation error {model.influence_error:.1e} of G's peak "
          f"at {len(model.check_x)} FEM presses between knots; dynamics error {model.reduction_error:.1e}")
    print(f"wrote {out}")
