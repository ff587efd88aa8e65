"""`taxel material fit-yeoh FILE --fit-strain S [--plot P] [--json]`: Yeoh
coefficients from a uniaxial tensile test, with the fitted law's stability range."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from taxel.cli.files import InputError, writable_file
from taxel.units import engineering as si


def register(sub):
    p = sub.add_parser("material", help="material tools (hyperelastic fits)")
    msub = p.add_subparsers(dest="material_command", required=True)
    p = msub.add_parser("fit-yeoh", help="fit an incompressible Yeoh law to a uniaxial tensile test")
    p.add_argument("file", help="CSV with engineering strain and engineering (nominal) stress columns")
    p.add_argument("--fit-strain", default="0.5", metavar="S",
                   help="fit points with 0 < strain <= S (fraction, or percent as '50%%'); default 0.5")
    p.add_argument("--check-strain", metavar="S", default=None,
                   help="check stability up to this tensile strain (default 2 x max strain) "
                        "and down to stretch 0.5 in compression")
    p.add_argument("--plot", metavar="OUT.png", help="write a plot of the data and the fit")
    p.add_argument("--json", action="store_true", help="print one JSON record")
    p.set_defaults(run=fit_yeoh_command)


def fit_yeoh_command(args):
    from taxel.fem.constitution import COMPRESSION_STRETCH, fit_yeoh, stability_losses
    from taxel.reports.figures import yeoh_fit as plot_fit
    from taxel.studies.uniaxial import read_uniaxial
    fit_strain = parse_strain("--fit-strain", args.fit_strain)
    if args.plot:
        writable_file(args.plot, "--plot", (".png", ".pdf", ".svg"))
    check = parse_strain("--check-strain", args.check_strain) if args.check_strain else 2.0 * fit_strain
    strain, stress = read_uniaxial(args.file)
    try:
        fit = fit_yeoh(strain, stress, fit_strain)
    except ValueError as exc:
        raise InputError(f"{args.file}: {exc}") from None
    lost = stability_losses(fit, (COMPRESSION_STRETCH, 1.0 + check))
    span = f"{100 * (COMPRESSION_STRETCH - 1):+.0f} % (stretch {COMPRESSION_STRETCH:g}) to {100 * check:+.0f} % strain"
    warnings = [f"WARNING: unstable in {r['mode']} {r['direction']} beyond {100 * r['strain']:+.1f} % strain "
                f"(stretch {r['stretch']:.3f}, {r['reason']}), inside the checked range {span}"
                for r in lost]
    if args.plot:
        try:
            plot_fit(strain, stress, fit, args.plot, check_strain=check,
                     title=f"{Path(args.file).name}: Yeoh fit to {100 * fit_strain:g} %")
        except OSError as exc:
            raise ValueError(f"cannot write plot {args.plot}: {exc.strerror or exc}") from None
    if args.json:
        rec = {"file": str(args.file), "C10_Pa": fit.C10, "C20_Pa": fit.C20, "C30_Pa": fit.C30,
               "r2": fit.r2, "n_points": fit.n_points, "rms_Pa": fit.rms_Pa, "fit_strain": fit.fit_strain,
               "check_strain": check, "check_stretch_min": COMPRESSION_STRETCH,
               "stability_lost": lost, "plot": args.plot}
        print(json.dumps(rec))
        for w in warnings:
            print(w, file=sys.stderr)
        return
    print(f"Yeoh fit to {args.file}: engineering strain vs nominal stress, "
          f"{fit.n_points} points with 0 < strain <= {100 * fit_strain:g} %")
    print(f"C10 = {fit.C10 / 1e3:.4g} kPa, C20 = {fit.C20 / 1e3:.4g} kPa, C30 = {fit.C30 / 1e3:.4g} kPa"
          f"  (mu = 2 C10 = {2 * fit.C10 / 1e3:.4g} kPa)")
    print(f"R^2 = {fit.r2:.5f}, RMS error {si(fit.rms_Pa, 'Pa')} over {fit.n_points} points")
    if not lost:
        print(f"stable in uniaxial, equibiaxial and pure shear from {span}")
    for w in warnings:
        print(w)
    if args.plot:
        print(f"plot written to {args.plot}")


def parse_strain(option: str, text) -> float:
    """A strain given as a fraction ('0.5') or a percentage ('50%', '50 %'); must be finite and > 0.

    Raises ValueError with one line naming `option` otherwise.
    """
    t = str(text).strip()
    pct = t.endswith("%")
    try:
        value = float(t.rstrip("%").strip()) / (100.0 if pct else 1.0)
    except ValueError:
        raise ValueError(f"{option} must be a number such as 0.5 or '50%', got '{text}'") from None
    if not (value > 0 and math.isfinite(value)):
        raise ValueError(f"{option} must be a positive strain (0.5 = 50 %), got '{text}'")
    return value


