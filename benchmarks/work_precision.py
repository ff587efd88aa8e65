"""The work-precision figures (docs/work-precision-<output>.png, one per
output; the every-panel grid docs/work-precision.png with --grid) and table: the four
thesis scenes at 0.2 N and 1 N, from the caches `taxel work-precision` filled
(out/work-precision-store; a first run solves everything: about 10-20 minutes, the
3x3 3D references most of it).

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/work_precision.py [--store DIR] [SCENE...]
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import taxel
from taxel.reports.work_precision import cheapest_rows, grid, questions, read, write

SCENES = ("thesis-pzt-single-2d", "thesis-pvdf-single-2d", "thesis-pzt-3x3-2d", "thesis-pvdf-3x3-2d")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--store", default="out/work-precision-store")
    ap.add_argument("--out", default="out/work-precision")
    ap.add_argument("--from", dest="folders", nargs="*", default=[],
                    help="redraw from folders `taxel work-precision` wrote (no solving)")
    ap.add_argument("--grid", action="store_true", help="also the every-panel grid, docs/work-precision.png")
    ap.add_argument("scenes", nargs="*", default=list(SCENES))
    args = ap.parse_args()
    if args.folders:
        wps = [w for f in args.folders for w in read(Path(f))]
        write(wps, Path(args.out))
    else:                                # taxel.work_precision writes the charts itself
        wps = taxel.work_precision(args.scenes, args.out, (0.2, 1.0), store=args.store)
    docs = Path(__file__).parent.parent / "docs"
    for path in questions(wps, docs):                # one figure per output, every model
        print(f"wrote {path}")
    if args.grid:
        grid(wps, docs / "work-precision.png")
    rec = json.loads((Path(args.out) / "work-precision.json").read_text())
    print("| scene | force (N) | output | within 1 % | within 5 % | within 10 % |\n|---|---|---|---|---|---|")
    for r in cheapest_rows(rec):
        print(f"| {r['scene']} | {r['force (N)']:g} | {r['output']} | {r['cheapest within 1 %']} | "
              f"{r['cheapest within 5 %']} | {r['cheapest within 10 %']} |")
    for w in rec["work_precision"]:
        print(f"- {w['scene']} at {w['force_N']:g} N: {w['how']}")


if __name__ == "__main__":
    main()
