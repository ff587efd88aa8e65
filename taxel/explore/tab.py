"""One page's explorer: its own design, answers, figures and 3D solve.

Every connection (a browser tab) has a Tab: the controls' values it sent, the
answers shown to it, and at most one of each kind of work: one update (the newest
design: a move while one is being answered replaces the waiting one), one figure,
one 3D solve. What a tab sends changes only its own design; what it is shown goes
to it alone (`push`). Parsing a value and solving run off the event loop, in the
explorer's lanes (app.Lanes); a tab that moves on or closes drops its waiting work,
and its 3D solve is ended.

An update: after a pause of DEBOUNCE for more moves, the design is applied to the
base scene (controls.scene_of: the scene schema's checks, as `taxel solve` makes
them; a refused value is shown beside its field and logged in one line), its solve
cost checked against the explorer's 2D cap (session.check_fits), and answered from
the study store or solved: a small solve in the fast lane, a large one in the slow
lane, so one large design never holds up the others' small ones. A design answered
lately (by any page) is answered from the explorer's memory (Explorer.recall), on the
event loop, without reading or solving it again.
"""

from __future__ import annotations

import asyncio
from dataclasses import dataclass, field

from taxel.explore import session as S
from taxel.explore.controls import NUMBERS, ControlValues, FieldError
from taxel.scene import Scene
from taxel.units import MAX_TEXT, engineering

DEBOUNCE = 0.02     # s: moves closer together than this are answered once
DESIGN = {f"t_{n.name}" for n in NUMBERS} | {"piezo", "load", "law", "model", "readout"}
# the state keys a page may set (the page's own schema); anything else is refused
CLIENT_KEYS = DESIGN | {f"x_{n.name}" for n in NUMBERS} | {"export_name"}


def check_change(key, value) -> str | None:
    """Why a client's state change is refused (one line), or None."""
    if not isinstance(key, str) or key not in CLIENT_KEYS:
        return f"the state key {str(key)[:40]!r} (not a control of this page)"
    if key.startswith("x_"):
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        return None if ok else f"{key}: a slider position must be a number"
    if isinstance(value, bool) or not isinstance(value, (str, int, float)):
        return f"{key}: expected text or a number, got {type(value).__name__}"
    if isinstance(value, str) and len(value) > MAX_TEXT:
        return f"{key}: a value of {len(value)} characters; at most {MAX_TEXT}"
    return None


@dataclass
class Tab:
    """One connection's page (see the module docstring)."""

    client: str
    explorer: object                           # app.Explorer: the base scene, lanes, session, publish
    state: dict                                # what this page shows (its state keys)
    generation: int = 0
    scene: Scene | None = None
    updating: asyncio.Task | None = None
    figure: asyncio.Task | None = None
    job3d: S.Job3D | None = None
    closed: bool = False
    tasks: set = field(default_factory=set)

    # -- what the page is shown -----------------------------------------------------------------
    def push(self, **changes) -> None:
        self.state.update(changes)
        if not self.closed:
            self.explorer.publish(self.client, changes)

    def design(self) -> ControlValues:
        st = self.state
        return ControlValues({n.name: str(st[f"t_{n.name}"]) for n in NUMBERS}, st["piezo"], st["load"],
                             st["law"], st["model"], st["readout"])

    def spawn(self, coro) -> asyncio.Task:
        task = asyncio.get_running_loop().create_task(coro)
        self.tasks.add(task)
        task.add_done_callback(self._done)
        return task

    def _done(self, task: asyncio.Task) -> None:
        self.tasks.discard(task)
        if not task.cancelled() and task.exception() is not None:     # a bug: one line, the page goes on
            exc = task.exception()
            self.explorer.refuse(self.client, f"internal error {type(exc).__name__}: {str(exc)[:160]}")
            self.push(busy=False, message=f"internal error: {type(exc).__name__} (the explorer goes on)")

    # -- a page's changes ------------------------------------------------------------------------
    def apply(self, changes: list[dict]) -> None:
        """A page's state changes: each checked (key from the page's schema, value's type
        and length) before it is kept; a design change starts an update."""
        moved = False
        for c in changes[:len(CLIENT_KEYS)]:
            key, value = c.get("key"), c.get("value")
            why = check_change(key, value)
            if why is not None:
                self.explorer.refuse(self.client, why)
                if key in DESIGN:                      # shown where the page shows that control's refusals
                    self.push(**({f"e_{key[2:]}": [why]} if key.startswith("t_") else
                                 {"e_piezo": [why]} if key == "piezo" else {"message": why}))
                continue
            self.state[key] = value
            moved |= key in DESIGN
        if len(changes) > len(CLIENT_KEYS):
            self.explorer.refuse(self.client, f"{len(changes)} changes in one message; at most {len(CLIENT_KEYS)}")
        if moved:
            self.changed()

    def changed(self) -> None:
        self.generation += 1
        if self.job3d is not None and self.job3d.running():
            self.job3d.cancel()
            self.push(busy3d=False, progress3d="3D solve cancelled: the design changed")
        if self.updating is None or self.updating.done():
            self.updating = self.spawn(self._update_loop())

    def close(self) -> None:
        """The page left: its waiting work is dropped, its 3D solve ended."""
        self.closed = True
        self.generation += 1
        if self.job3d is not None and self.job3d.running():
            self.job3d.cancel()
        for t in list(self.tasks):
            t.cancel()

    # -- updates ---------------------------------------------------------------------------------
    async def _update_loop(self):
        while not self.closed:
            gen = self.generation
            await asyncio.sleep(DEBOUNCE)
            if gen != self.generation:
                continue
            await self._update(gen)
            if gen == self.generation:
                return

    async def _update(self, gen: int):
        ex = self.explorer
        loop = asyncio.get_running_loop()
        design = self.design()
        hit = ex.recall(design)                        # a design answered lately, by any page
        if hit is not None:
            self.scene = hit[0]
            self.push(**{f"e_{n.name}": [] for n in NUMBERS}, e_piezo=[], message="", **self._shown(hit[1]),
                      busy=False, answers=self.state["answers"] + 1)
            if ex.front is not None:
                await self._plot_front(hit[1], hit[0], gen)
            return
        try:
            scene, cost = await loop.run_in_executor(ex.lanes.fast, ex.prepare, design)
        except FieldError as exc:
            if gen == self.generation:
                self._refused(exc)
            return
        if gen != self.generation:
            return
        self.push(**{f"e_{n.name}": [] for n in NUMBERS}, e_piezo=[], message="", busy=True)
        lane = ex.lanes.fast if cost.unknowns <= ex.lanes.small else ex.lanes.slow

        def work():
            return ex.answer(scene) if gen == self.generation else None
        try:
            ans = await loop.run_in_executor(lane, work)
        except Exception as exc:                       # a failed solve: its one line, the page goes on
            self.push(message=f"the solve failed: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}",
                      busy=False)
            return
        if ans is None or gen != self.generation:
            return
        self.scene = scene
        ex.remember(design, scene, ans)
        self.push(**self._shown(ans), busy=False, answers=self.state["answers"] + 1)
        if ex.front is not None:
            await self._plot_front(ans, scene, gen)

    def _refused(self, exc: FieldError) -> None:
        self.explorer.refuse(self.client, str(exc))
        fields = {n.name for n in NUMBERS}
        self.push(**{f"e_{n.name}": [str(exc)] if exc.field == n.name else [] for n in NUMBERS},
                  e_piezo=[str(exc)] if exc.field == "piezo" else [],
                  message="" if exc.field in fields | {"piezo"} else str(exc), busy=False)

    @staticmethod
    def _shown(a: S.Answer) -> dict:
        v = a.pressed_voltage
        top = max((abs(x) for x in a.voltages.values()), default=1.0) or 1.0
        return {"voltage": engineering(v, "V") if v is not None else "-", "answer_model": a.model,
                "answer_time": ("from the store" if a.cached else "solved") + f" in {a.seconds * 1e3:.0f} ms",
                "bars": [{"name": k, "text": engineering(x, "V"), "width": f"{100 * abs(x) / top:.1f}%",
                          "colour": "#c0392b" if x < 0 else "#2e86c1"} for k, x in a.voltages.items()],
                "crosstalk": f"{100 * a.crosstalk:.1f} %" if a.crosstalk is not None else "- (one taxel)",
                "note": a.note}

    async def _plot_front(self, a: S.Answer, scene: Scene, gen: int):
        ex = self.explorer
        v, f = a.pressed_voltage, scene.load.force
        current = (abs(v) / f, a.crosstalk) if v is not None and f and a.crosstalk is not None else None
        url = await asyncio.get_running_loop().run_in_executor(ex.lanes.fast, ex.front.image, current)
        if gen == self.generation:
            self.push(front_image=url, front_current=(
                "current design (the star): -" if current is None else
                f"current design (the star): {current[0]:.4g} V/N, {100 * current[1]:.2f} %"))

    # -- figures on request: one at a time per page, in the slow lane ------------------------------------
    def extra(self, title: str, fn) -> None:
        scene = self.scene
        if scene is None:
            return
        if self.figure is not None and not self.figure.done():
            self.explorer.refuse(self.client, f"{title}: a figure is being made for this page already")
            return
        self.push(figure_title=f"{title}: working...", extra_busy=True)

        async def run():
            try:
                out = await asyncio.get_running_loop().run_in_executor(self.explorer.lanes.slow, fn, scene)
                msg = title
            except Exception as exc:
                out, msg = None, f"{title} failed: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}"
            if isinstance(out, list):
                self.push(error_lines=out)
            elif out is not None:
                self.push(figure=out)
            self.push(figure_title=msg, extra_busy=False)
        self.figure = self.spawn(run())

    # -- 3D: one solve at a time in the explorer -------------------------------------------------------
    def solve_3d(self) -> None:
        ex = self.explorer
        if self.scene is None or self.job3d is not None and self.job3d.running():
            return
        busy = [t for t in ex.tabs.values() if t.job3d is not None and t.job3d.running()]
        if busy:
            self.push(progress3d="another page's 3D solve is running (one at a time); try again when it ends")
            return
        try:
            self.job3d = job = ex.session().start_3d(self.scene)
        except (S.TooLarge, ValueError) as exc:          # refused before it starts, with its size
            self.push(busy3d=False, progress3d=str(exc).splitlines()[0], answer3d="")
            return
        self.push(busy3d=True, progress3d="3D solve started (coarse mesh)", answer3d="")
        self.spawn(self._watch_3d(job))

    async def _watch_3d(self, job: S.Job3D):
        try:
            while job.running():
                self.push(progress3d=f"3D solve running (coarse mesh): {job.elapsed:.1f} s")
                await asyncio.sleep(0.25)
        except asyncio.CancelledError:
            job.cancel()
            raise
        if job.cancelled:
            return
        try:
            a = job.result()
            text = f"3D: {engineering(a.pressed_voltage, 'V')} ({a.model}, coarse mesh, {a.seconds:.1f} s)"
        except RuntimeError as exc:
            text = f"3D solve failed: {exc}"
        self.push(busy3d=False, progress3d="3D solve done", answer3d=text)
