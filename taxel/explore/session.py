"""The explorer's solving side: a design in, an answer out, fast and cached.

`Session.answer(scene)` is one static solve through the study store
(`studies.store.Store.get_or_compute`): the store is keyed by the validated scene
and the code version, so a design seen before (going back on a slider) is read,
not solved. The 2D and axisymmetric models answer in a fraction of a second.

A 3D solve (`Session.start_3d`) runs in its own process on a coarse mesh, so it
never holds up a 2D answer (of this user or another); `Job3D.poll` reports its
progress (elapsed time, unknowns when done) and `Job3D.cancel` ends it when a
control moves on. The finished 3D point is stored like any other.

On request: the deformed section coloured by potential, the error estimate of
the current model, the frequency response through the readout, and a probe's
voltage-force curve (each force a cached point of the store).
"""

from __future__ import annotations

import base64
import io
import multiprocessing
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

from taxel.scene import Scene, replace
from taxel.schema import to_data
from taxel.studies.store import Store

OUTPUTS = ("voltage", "crosstalk", "max_strain")
MODEL_NAMES = {"plane_strain": "2D (plane strain)", "plane_stress": "2D (plane stress)",
               "axisymmetric": "axisymmetric", "3d": "3D"}


@dataclass
class Answer:
    """One design's numbers: open-circuit voltage per taxel (V), the pressed taxel,
    crosstalk (largest neighbour / pressed, or None), the model that produced it and
    the seconds it took (0 solve seconds and `cached` when read from the store)."""

    voltages: dict[str, float]
    pressed: str | None
    crosstalk: float | None
    max_strain: float
    model: str
    seconds: float
    cached: bool
    note: str = ""

    @property
    def pressed_voltage(self) -> float | None:
        return self.voltages.get(self.pressed) if self.pressed else None


def scene_data(scene: Scene) -> dict:
    """The scene as the store's point data (TOML-like strings with SI units)."""
    return to_data(scene)


def _answer(scene: Scene, row: tuple, seconds: float, cached: bool) -> Answer:
    status, result, error = row
    if status != "done":
        raise RuntimeError(error or "the solve failed")
    return Answer(dict(result["voltage"]), result.get("pressed"), result.get("crosstalk"),
                  float(result.get("max_strain", 0.0)), MODEL_NAMES[scene.model.type], seconds, cached,
                  result.get("model_note") or "")


class Session:
    """Answers for one explorer: a study store in `folder` (a fresh temporary
    folder when None). Use one Session per thread: a Store holds an SQLite
    connection, which stays in the thread that opened it."""

    def __init__(self, folder: str | Path | None = None):
        self.folder = Path(folder) if folder is not None else Path(tempfile.mkdtemp(prefix="taxel-explore-"))
        self._store: Store | None = None

    @property
    def store(self) -> Store:
        if self._store is None:
            self._store = Store(self.folder)
        return self._store

    def cached(self, scene: Scene) -> bool:
        from taxel.studies.store import point_key
        row = self.store.get(point_key(scene_data(scene)))
        return row is not None and row["status"] == "done"

    def answer(self, scene: Scene) -> Answer:
        """The static answer of a scene, from the store or solved now (and stored)."""
        from taxel.studies.store import point_key
        t0 = time.perf_counter()
        data = scene_data(scene)
        stored = self.store.get(point_key(data))               # one look-up when the design is stored
        hit = stored is not None and stored["status"] == "done"
        row = ("done", stored["result"], None) if hit else \
            self.store.get_or_compute(data, OUTPUTS, {"scene": scene.name})
        return _answer(scene, row, time.perf_counter() - t0, hit)

    def force_curve(self, scene: Scene, forces) -> list[tuple[float, float]]:
        """(force N, pressed-taxel voltage V) at each force: a probe's voltage-force curve."""
        out = []
        for f in forces:
            a = self.answer(replace(scene, **{"load.force": float(f)}))
            out.append((float(f), a.pressed_voltage))
        return out

    def start_3d(self, scene: Scene) -> Job3D:
        """The scene as a coarse 3D model (mesh 1.5 mm, piezo 0.6 mm), solved in a new process;
        Refused (TooLarge) where its solve would need more than MEMORY_3D of this machine."""
        coarse = coarse_3d(scene)
        check_fits(coarse)
        ctx = multiprocessing.get_context("spawn")
        proc = ctx.Process(target=_solve_in_store, args=(scene_data(coarse), str(self.folder)), daemon=True)
        proc.start()
        return Job3D(coarse, proc, self.folder)

    def close(self):
        if self._store is not None:
            self._store.close()
            self._store = None


# The explorer's memory caps, as shares of this machine's memory (meshing.cost.machine_memory),
# chosen so that they add up: at once run at most the one 3D solve (MEMORY_3D), the slow lane's
# one 2D solve or figure (MEMORY_2D) and the fast lane's small solves (app.FAST_WORKERS of at most
# SMALL_UNKNOWNS unknowns, about 0.15 GB each): together within MEMORY_BUDGET, the rest of the
# machine left to whatever else it runs. On a 24 GB machine (25.3 GB): 6.3 + 2.5 + 0.3 GB.
MEMORY_3D = 0.25
MEMORY_2D = 0.10
SMALL_UNKNOWNS = 50_000        # a 2D solve answered in the fast lane (the thesis taxel: 4k unknowns)
MEMORY_BUDGET = 0.40


class TooLarge(ValueError):
    """A 3D solve refused before it starts: its estimated size, and the cap."""


def coarse_3d(scene: Scene) -> Scene:
    """The explorer's 3D model of a scene: its coarse mesh (1.5 mm, piezo 0.6 mm)."""
    return replace(scene, **{"model.type": "3d", "mesh.size": max(scene.mesh.size, 1.5e-3),
                             "mesh.piezo_size": max(scene.mesh.piezo_size or 0.0, 0.6e-3)})


def check_fits(scene: Scene, share: float = MEMORY_3D):
    """The scene's solve cost (meshing.cost), or TooLarge where it needs more than
    `share` of this machine's memory."""
    from taxel.analyses.model.geometry import layout, solve_limit
    from taxel.analyses.model.problem import scene_materials
    from taxel.meshing.cost import solve_cost
    lay = layout(scene, scene_materials(scene))
    lim = solve_limit(scene, lay)
    cost = solve_cost(lay, lim.order, lim.krylov)
    if cost.bytes > share * cost.memory:
        raise TooLarge(f"{MODEL_NAMES.get(scene.model.type, scene.model.type)} solve refused: about {cost.unknowns:.3g} unknowns, needing about "
                       f"{cost.bytes / 1e9:.3g} GB, more than the explorer's {share * cost.memory / 1e9:.3g} GB "
                       f"({100 * share:.0f} % of this machine's memory); make the design smaller")
    return cost


def _solve_in_store(data: dict, folder: str) -> None:
    """A background process: one point solved into the store (the parent reads it)."""
    store = Store(Path(folder))
    store.get_or_compute(data, OUTPUTS, {"scene": "3d"})
    store.close()


@dataclass
class Job3D:
    """A 3D solve in its own process."""

    scene: Scene
    process: multiprocessing.Process
    folder: Path
    started: float = field(default_factory=time.perf_counter)
    cancelled: bool = False

    @property
    def elapsed(self) -> float:
        return time.perf_counter() - self.started

    def running(self) -> bool:
        return self.process.is_alive()

    def cancel(self) -> None:
        """End the solve now (the design it was for is no longer shown)."""
        if self.process.is_alive():
            self.process.terminate()
            self.process.join(5)
        self.cancelled = True

    def result(self) -> Answer:
        """The finished answer (read from the store)."""
        from taxel.studies.store import point_key
        store = Store(self.folder)
        try:
            row = store.get(point_key(scene_data(self.scene)))
        finally:
            store.close()
        if row is None:
            code = self.process.exitcode
            if code is not None and code < 0:
                import signal
                name = signal.Signals(-code).name if -code in signal.valid_signals() else f"signal {-code}"
                raise RuntimeError(f"the 3D solve's process was killed ({name}{', out of memory?' if -code == 9 else ''})"
                                   "; nothing was stored; the explorer goes on, solve in 3D again to retry")
            raise RuntimeError(f"the 3D solve ended without a result (exit code {code})")
        return _answer(self.scene, (row["status"], row["result"], row["error"]), self.elapsed, False)


def png_data_url(fig) -> str:
    """A matplotlib figure as a PNG data URL (for an <img> in the page)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode()


def section_image(scene: Scene) -> str:
    """The deformed section coloured by the potential (a fresh 2D solve; reports.figures)."""
    from taxel.analyses import solve
    from taxel.analyses.results.figures import cross_section
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "section.png"
        cross_section(solve(scene), path)
        return "data:image/png;base64," + base64.b64encode(path.read_bytes()).decode()


def error_lines(scene: Scene) -> list[str]:
    """The error estimate of the current model (taxel.analyses.accuracy.error_estimate)."""
    from taxel.analyses import solve
    res = solve(scene, estimate=True)
    return res.error.lines() if res.error is not None else ["error: no estimate for this model"]


def frequency_image(scene: Scene) -> str:
    """The frequency response through the scene's readout (a reduced sweep)."""
    from taxel.analyses import frequency
    from taxel.analyses.results.dynamic_figures import bode
    fr = frequency(replace(scene, **{"analysis.type": "frequency", "analysis.method": "reduced",
                                     "analysis.points": 60}))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bode.png"
        bode(fr.freqs, fr.output, fr.names, fr.label, path, f"{MODEL_NAMES[scene.model.type]}, {fr.label}")
        return "data:image/png;base64," + base64.b64encode(path.read_bytes()).decode()


def curve_image(points: list[tuple[float, float]], title: str) -> str:
    """The voltage-force curve of a probe."""
    from taxel.reports.figures import pyplot
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 3.2), constrained_layout=True)
    ax.plot([p[0] for p in points], [p[1] for p in points], "o-")
    ax.set_xlabel("force (N)")
    ax.set_ylabel("pressed-taxel voltage (V)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    url = png_data_url(fig)
    plt.close(fig)
    return url


