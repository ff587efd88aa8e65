"""The answer's designs pressed in 3D (main job): for each optimization folder, the
recommended and the thesis design its probe front chose, and the design each binding
requirement's relaxation would choose (FrontAnswer.priced; a design named twice is pressed once) (reports.answer.headline_front,
on the candidate-selection model) pressed in 3D by the rig's probe on Yeoh silicone
(optimize.answer_press: one `taxel.solve` each, the 3x3 quarter on the default press
mesh, with the press family's calibrated error estimate), all designs of all folders on
one pool of workers. Each press's result folder, ROOT/<front>-<role>-3d, is the design's
3D view on the report (the same solve as the answer's numbers); the numbers go into the
folder's probe-front.json, where the answer reads them.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path


def answer_presses(root: Path, names: list[str], workers: int = 2) -> list[Path]:
    """Press the answer designs of ROOT/<name> for each built-in front `name` (its
    -probe-front problem's [press]); returns the presses' result folders."""
    from taxel.optimize import answer_press as AP
    from taxel.optimize import spec as O
    from taxel.reports.answer import headline_front
    t0 = time.perf_counter()
    jobs, owners = [], []
    for name in names:
        folder = root / name
        a = headline_front(folder)
        if a is None:
            continue
        probe = O.load_optimization(name.replace("-front", "-probe-front"), folder)
        for d in (a.recommended, a.thesis, *(d for _, d in a.priced)):   # and what relaxing a requirement buys
            if d is None:
                continue
            x_mm = {"silicone_above": d.silicone_above_mm, "silicone_below": d.silicone_below_mm, "gap": d.gap_mm}
            x = [x_mm[n] for n in probe.names]
            owners.append((folder, d.role, x))
            if any(o[0] == folder and all(abs(u - v) < 1e-9 for u, v in zip(o[2], x)) for o in owners[:-1]):
                continue                     # a design named twice (a relaxation choosing the thesis design): one press
            view = f"{name.removesuffix('-front')}-{d.role}-3d"
            data = AP.scene_data(probe, x)
            data["name"] = view
            shutil.rmtree(root / view, ignore_errors=True)
            jobs.append((view, data, str(root / view)))
    got = AP.press_all(jobs, workers)
    pressed = [(folder, x, r) for (folder, _, x), r in zip(_firsts(owners), got)]
    by_folder: dict[Path, list] = {}
    for folder, role, x in owners:
        r = next(r for f, y, r in pressed if f == folder and all(abs(u - v) < 1e-9 for u, v in zip(y, x)))
        by_folder.setdefault(folder, []).append(AP.AnswerPress(role, x, **r))
    for folder, presses in by_folder.items():
        AP.write(folder, presses)
        for p in presses:
            print(f"      {folder.name} {p.role}: " + (
                f"3D press {p.sensitivity:.4g} V/N at {100 * p.crosstalk:.3g} % crosstalk, estimated error "
                f"{100 * p.error:.2g} % / {100 * p.crosstalk_error:.2g} %, {p.unknowns} unknowns, {p.seconds:.0f} s"
                if p.failed is None and p.error is not None else
                f"3D press {p.sensitivity} V/N, no estimate" if p.failed is None else f"failed: {p.failed}"))
    print(f"      {len(jobs)} 3D presses of the answer's designs in {time.perf_counter() - t0:.0f} s", flush=True)
    return [Path(out) for (_, _, out), r in zip(jobs, got) if r.get("failed") is None]


def _firsts(owners: list[tuple]) -> list[tuple]:
    """The first (folder, role, x) of each design of each folder: the ones pressed."""
    out: list[tuple] = []
    for o in owners:
        if not any(f == o[0] and all(abs(u - v) < 1e-9 for u, v in zip(x, o[2])) for f, _, x in out):
            out.append(o)
    return out
