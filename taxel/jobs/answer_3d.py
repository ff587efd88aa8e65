"""The answer's designs judged and pressed in 3D (main job): for each optimization folder,
its coverage judged on 3D surface maps (taxel.jobs.answer_coverage: it can change the
recommendation), then the recommended and the thesis design its probe front chose, and the
design each binding requirement's relaxation would choose (the answer's owner,
optimize.answer_folder.FolderAnswer: answer_designs, on the candidate-selection model) pressed in 3D by the
rig's probe on Yeoh silicone (optimize.answer_press: one `taxel.solve` each, the 3x3
quarter on the default press mesh, with the press family's calibrated error estimate).

One pool of workers does it all (`answer_designs`): each folder's coverage and each
thesis design's press start at once (the thesis design is pressed whatever the coverage
says); a folder's other designs are pressed as soon as its coverage has chosen them, ahead
of the presses still waiting. A design named twice (a relaxation choosing the thesis
design) is pressed once. Each press's result folder, ROOT/<front>-<role>-3d, is the
design's 3D view on the report (the same solve as the answer's numbers); the owner writes
the numbers into the folder's probe-front.json (FolderAnswer.write_presses), where it reads them.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path


def _designs(root: Path, name: str, roles: tuple[str, ...] | None = None):
    """The answer's owner of ROOT/<name> (None when it holds no answer) and (role, x, scene
    data) of its answer designs (its -probe-front problem's [press]), in the answer's order
    (recommended, thesis, priced), each design once; only `roles` when given ("thesis")."""
    from taxel.optimize import answer_press as AP
    from taxel.optimize import spec as O
    from taxel.optimize.answer_folder import FolderAnswer
    folder = root / name
    a = FolderAnswer.read(folder)
    if a is None:
        return None, []
    probe = O.load_optimization(name.replace("-front", "-probe-front"), folder)
    out = []
    for d in a.answer_designs(roles):           # and what relaxing a requirement buys
        x = d.vector(probe.names)
        data = AP.scene_data(probe, x)
        data["name"] = f"{name.removesuffix('-front')}-{d.label}-3d"
        out.append((d.label, x, data))
    return a, out


def _same(x, y) -> bool:
    return all(abs(u - v) < 1e-9 for u, v in zip(x, y))


def answer_designs(root: Path, names: list[str], workers: int = 2, press: bool = True) -> list[Path]:
    """Judge the coverage of the answers of ROOT/<name> for each built-in front `name` and press
    their designs in 3D (module docstring; `press` False: the coverage only); returns the
    presses' result folders."""
    from dask.distributed import Client, as_completed
    from taxel.jobs.answer_coverage import answer_coverage
    from taxel.optimize import answer_press as AP
    from taxel.studies.execute import local_cluster
    t0 = time.perf_counter()
    cluster = local_cluster(workers)
    client = Client(cluster)
    pressed: dict[str, list] = {n: [] for n in names}       # name -> [(x, data, future)]
    chosen: dict[str, tuple] = {}                            # name -> (owner, its answer designs): read once

    def submit(name, x, data, priority):
        if any(_same(x, y) for y, _, _ in pressed[name]):
            return
        out = root / data["name"]
        shutil.rmtree(out, ignore_errors=True)
        pressed[name].append((x, data, client.submit(AP.press, data, str(out), AP.PRESS_3D, pure=False,
                                                     priority=priority)))
    try:
        judged = {client.submit(answer_coverage, root / n, pure=False, priority=2): n for n in names}
        for n in names if press else []:        # the thesis design is pressed whatever the coverage says
            for _, x, data in _designs(root, n, ("thesis",))[1]:
                submit(n, x, data, 0)
        for fut in as_completed(list(judged)):
            n = judged[fut]
            print(f"      {n}: the answer's coverage (optimize.coverage) judged in {fut.result():.0f} s", flush=True)
            chosen[n] = _designs(root, n)               # the owner after the coverage, and its designs
            for _, x, data in (chosen[n][1] if press else []):   # the designs the coverage chose: next
                submit(n, x, data, 1)
        got = {n: [(x, data, f.result()) for x, data, f in pressed[n]] for n in names}
    finally:
        client.close()
        cluster.close()
    views = []
    for n in names:
        if not got[n]:
            continue
        owner, designs = chosen[n]
        presses = []
        for role, x, _ in designs:
            _, data, r = next(g for g in got[n] if _same(g[0], x))
            presses.append(AP.AnswerPress(role, x, **r))
            print(f"      {n} {role}: " + (
                f"3D press {r['sensitivity']:.4g} V/N at {100 * r['crosstalk']:.3g} % crosstalk, estimated error "
                f"{100 * r['error']:.2g} % / {100 * r['crosstalk_error']:.2g} %, {r['unknowns']} unknowns, "
                f"{r['seconds']:.0f} s" if r.get("failed") is None and r.get("error") is not None else
                f"3D press {r.get('sensitivity')} V/N, no estimate" if r.get("failed") is None else
                f"failed: {r['failed']}"))
        owner.write_presses(presses)
        views += [root / data["name"] for _, data, r in got[n] if r.get("failed") is None]
    print(f"      {sum(len(v) for v in got.values())} 3D presses of the answer's designs, coverage judged, in "
          f"{time.perf_counter() - t0:.0f} s", flush=True)
    return views
