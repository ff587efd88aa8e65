"""Coulomb friction against an independent code: FELupe 11.3's ContactRigidCylinder
(penalty normal and tangential contact, Coulomb return mapping, `friction=mu`) and
fem.contact (augmented Lagrangian, return mapping on the tangential multipliers).

Problem (plane strain, per metre of depth): a Yeoh Ecoflex block 4 mm wide, 2 mm high,
bonded at the bottom, free sides; (C10, C20, C30) = (7.83e3, 0.103e3, -0.8) Pa,
K = 5 MPa; a rigid cylinder of radius 2 mm pressed 0.28 mm in 14 equal travel steps
(the same steps in both codes: friction depends on the path). FELupe: Q1/P0/P0 mixed
quadrilaterals (`FieldsMixed`, `NearlyIncompressible` Yeoh), 80 x 40, its top nodes the
contact points; its penalties (normal = tangential = m x 2 C10, per node) leave a
penetration and an elastic slip of order 1/m, so its force is extrapolated to an
infinite penalty from m = 10 and 20 (F = F2 + (F2 - F1) m1 / (m2 - m1), error ~ 1/m; at
mu = 0, m = 10, 30, 100 give 21.04, 21.38, 21.50 N/m, extrapolated from 10 and 30: 21.54;
at 30 FELupe's Newton does not converge with mu = 0.1 or 0.3).
Ours: P2/P1 Taylor-Hood triangles, h = 0.1 mm (h = 0.05 mm with --refine), two Gauss
points per top edge.
Slip zone: the contact half-width a (the outermost point in contact) and the stick
half-width c (the outermost sticking point), each code at its own points (FELupe's
nodes every 0.05 mm, ours the Gauss points): they agree to about a point spacing.
(The JSON's friction_half_* compare the friction force on the half x > 0: FELupe's from
its contact's nodal force vector; at mu = 0.1 1.124 against our 1.084 N/m, at 0.3 and 1
0.46 and 0.43 against 2.21 and 2.41: not reconciled, FELupe's last evaluated contact
force may not be the converged state's. Not a claim.)

Measured (one run, load 8-15 on 2 cores): at 0.28 mm, ours / FELupe extrapolated
  mu = 0.1: 22.138 / 22.113 N/m, largest difference over the curve 0.55 %; a 0.781 / 0.812 mm, c 0.021 / 0.000 mm
  mu = 0.3: 23.108 / 23.075 N/m, 0.58 %; a 0.756 / 0.789 mm, c 0.382 / 0.353 mm
  mu = 1.0: 23.366 / 23.336 N/m, 0.67 %; a 0.745 / 0.778 mm, c = a (all stick)
and frictionless 21.573 against 21.544 (penalties 10 and 30).

With --3d: FELupe's ContactRigidPlane(friction=mu) compressing a bonded Yeoh block 4 x 4 x 2 mm
(the quarter, two symmetry planes) by 0.2 mm in 10 steps, on the same grid of nodes (FELupe
Q1/P0/P0 hexahedra 8 per edge, ours P2/P1 tetrahedra six per hexahedron; tests/felupe_contact.py).
Measured (one run, load 7-8): at 0.2 mm, ours / FELupe extrapolated (penalties 10 and 20)
  mu = 0.1: 0.11059 / 0.11064 N, largest difference over the curve 0.17 %; all slip in both
  mu = 0.3: 0.12675 / 0.12681 N, 0.26 %; stick radius 0.639 / 0.710 mm, stick or slip the same
            at 50 of the 55 nodes both touch
  mu = 1.0: 0.14353 / 0.14551 N, 1.36 % (FELupe at penalties 40 and 80: 0.14311, 0.14457 N,
            converging to about 0.1460 N; ours on 4 per edge 0.14651 N); the same at 37 of 55
CPU: ours 23-80 s, FELupe 11-17 s per coefficient.

Run: MKL_NUM_THREADS=1 OMP_NUM_THREADS=1 python benchmarks/friction_felupe.py [--mu 0.1 0.3 1.0] [--3d]
writes benchmarks/out/friction_felupe.json and docs/contact-friction-felupe.png
(--3d: benchmarks/out/friction_felupe_3d.json and docs/contact-friction-felupe-3d.png).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from taxel.fem.contact import OPEN, SLIP, STICK

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from felupe_contact import (TRAVEL, TRAVEL_3D, felupe_extrapolated, felupe_extrapolated_3d, ours,  # noqa: E402
                            ours_3d, same_nodes, travels, travels_3d)

def figure(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (ax, az) = plt.subplots(1, 2, figsize=(10, 4))
    d = 1e3 * travels()
    for k, (mu, o, f) in enumerate(rows):
        c = f"C{k}"
        ax.plot(d, o["F"], "-", color=c, label=f"mu = {mu}: taxel")
        ax.plot(d, f["F"], "o", color=c, mfc="none", label=f"mu = {mu}: FELupe (extrapolated)")
        for j, (res, name) in enumerate(((o, "taxel"), (f, "FELupe"))):
            y = 2 * k + 0.4 * j
            for state, col in ((1, "tab:blue"), (2, "tab:orange")):
                sel = (res["zone"] == state) & (res["x"] >= 0)
                az.plot(1e3 * res["x"][sel], np.full(sel.sum(), y), "|", color=col, ms=8)
            az.text(1.05, y, f"mu = {mu} {name}", va="center", fontsize=8)
    ax.set_xlabel("travel (mm)")
    ax.set_ylabel("force (N per m of depth)")
    ax.legend(fontsize=7)
    ax.set_title("rigid cylinder R = 2 mm on a Yeoh block")
    az.set_xlim(0, 1.6)
    az.set_yticks([])
    az.set_xlabel("x (mm), deformed; blue stick, orange slip")
    az.set_title("slip zone at 0.28 mm")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def figure_3d(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 1 + len(rows), figsize=(4 + 3 * len(rows), 3.6))
    ax = axes[0]
    d = 1e3 * travels_3d()
    for k, (mu, o, f) in enumerate(rows):
        ax.plot(d, o["F"], "-", color=f"C{k}", label=f"mu = {mu}: taxel")
        ax.plot(d, f["F"], "o", color=f"C{k}", mfc="none", label=f"mu = {mu}: FELupe (extrapolated)")
        az = axes[k + 1]
        for res, marker, size in ((o, ".", 4), (f, "s", 30)):
            for state, col in ((STICK, "tab:blue"), (SLIP, "tab:orange")):
                sel = res["zone"] == state
                az.scatter(1e3 * res["xy"][sel, 0], 1e3 * res["xy"][sel, 1], s=size, marker=marker, color=col,
                           facecolors="none" if marker == "s" else col, linewidths=0.8)
        az.set_aspect("equal")
        az.set_title(f"mu = {mu}: stick (blue), slip (orange)", fontsize=8)
        az.set_xlabel("x (mm), deformed; squares FELupe", fontsize=8)
    ax.set_xlabel("travel (mm)")
    ax.set_ylabel("force (N, the whole block)")
    ax.legend(fontsize=6)
    ax.set_title("3D: rigid plate on a Yeoh block", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main_3d(mus):
    """The 3D comparison: FELupe's ContactRigidPlane(friction=mu) on Q1/P0 hexahedra against
    our plate on P2/P1 tetrahedra of the same grid (tests/felupe_contact.py)."""
    out, rows = {}, []
    for mu in mus:
        t0 = time.process_time()
        o = ours_3d(mu)
        t1 = time.process_time()
        f = felupe_extrapolated_3d(mu)
        t2 = time.process_time()
        zo, zf = same_nodes(o, f)
        both = (zo != OPEN) & (zf != OPEN)
        rows.append((mu, o, f))
        out[str(mu)] = dict(ours_N=o["F"].tolist(), felupe_N=f["F"].tolist(),
                            felupe_penalties_N=[F.tolist() for F in f["F_penalties"]],
                            rel_diff=(o["F"] / f["F"] - 1).tolist(), stick_radius_ours_m=o["c"],
                            stick_radius_felupe_m=f["c"], nodes_compared=int(zo.size),
                            nodes_in_contact_in_both=int(both.sum()),
                            nodes_same_stick_or_slip=int((zo[both] == zf[both]).sum()),
                            cpu_s_ours=t1 - t0, cpu_s_felupe=t2 - t1)
        print(f"3D mu = {mu}: F at {1e3 * TRAVEL_3D:g} mm ours {o['F'][-1]:.5f}, FELupe {f['F'][-1]:.5f} N "
              f"(largest |diff| over the curve {100 * np.abs(o['F'] / f['F'] - 1).max():.2f} %); stick radius "
              f"{1e3 * o['c']:.3f} / {1e3 * f['c']:.3f} mm; of FELupe's {zo.size} top nodes {both.sum()} in contact in "
              f"both, {(zo[both] == zf[both]).sum()} of them in the same state (stick or slip); "
              f"CPU {t1 - t0:.0f} / {t2 - t1:.0f} s", flush=True)
    Path("benchmarks/out").mkdir(parents=True, exist_ok=True)
    Path("benchmarks/out/friction_felupe_3d.json").write_text(json.dumps(out, indent=1))
    figure_3d(rows, "docs/contact-friction-felupe-3d.png")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mu", type=float, nargs="+", default=[0.1, 0.3, 1.0])
    ap.add_argument("--refine", action="store_true", help="ours also at h = 0.05 mm")
    ap.add_argument("--3d", dest="three_d", action="store_true", help="the 3D plate instead (below)")
    args = ap.parse_args()
    if args.three_d:
        return main_3d(args.mu)
    out, rows = {}, []
    for mu in args.mu:
        t0 = time.process_time()
        o = ours(mu)
        t1 = time.process_time()
        f = felupe_extrapolated(mu)
        t2 = time.process_time()
        rows.append((mu, o, f))
        rec = dict(ours_N_per_m=o["F"].tolist(), felupe_N_per_m=f["F"].tolist(),
                   felupe_penalties_N_per_m=[F.tolist() for F in f["F_penalties"]],
                   rel_diff=(o["F"] / f["F"] - 1).tolist(), a_ours_m=o["a"], a_felupe_m=f["a"],
                   c_ours_m=o["c"], c_felupe_m=f["c"], friction_half_ours_N_per_m=o["Ft"],
                   friction_half_felupe_N_per_m=f["Ft"], cpu_s_ours=t1 - t0, cpu_s_felupe=t2 - t1)
        if args.refine:
            rec["ours_h_0.05mm_N_per_m"] = ours(mu, h=5e-5)["F"].tolist()
        out[str(mu)] = rec
        print(f"mu = {mu}: F at {1e3 * TRAVEL:g} mm ours {o['F'][-1]:.4f}, FELupe {f['F'][-1]:.4f} N/m "
              f"(largest |diff| over the curve {100 * np.abs(o['F'] / f['F'] - 1).max():.2f} %); contact a "
              f"{1e3 * o['a']:.3f} / {1e3 * f['a']:.3f} mm, stick c {1e3 * o['c']:.3f} / {1e3 * f['c']:.3f} mm",
              flush=True)
    Path("benchmarks/out").mkdir(parents=True, exist_ok=True)
    Path("benchmarks/out/friction_felupe.json").write_text(json.dumps(out, indent=1))
    figure(rows, "docs/contact-friction-felupe.png")


if __name__ == "__main__":
    main()
