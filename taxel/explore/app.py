"""The explorer's page (trame, pyvista's web backend; Vue 3 + Vuetify 3).

Every control is a slider and a text field in its display unit, or a choice.
A moved control starts an update: after a short pause for more moves (20 ms),
the design is applied to the base scene (a refused value shows the scene's
one-line message beside its field) and answered by the session's worker thread
(the study store: a design seen before is read, not solved). A stale update
(a newer move came in) is dropped before it is solved, and its answer is never
shown. 3D runs in a separate process (session.Job3D), polled here; a moved
control cancels it. Figures on request (section, error estimate, frequency
response, voltage-force curve) run in a second worker, so they never hold up
the numbers.
"""

from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from trame.app import asynchronous, get_server
from trame.ui.vuetify3 import SinglePageLayout
from trame.widgets import html, vuetify3 as v3

from taxel.explore import session as S
from taxel.explore.front import Front
from taxel.explore.controls import LAWS, LOADS, MODELS, NUMBERS, READOUTS, ControlValues, FieldError, piezo_names, scene_of
from taxel.scene import Scene
from taxel.schema import to_data
from taxel.units import engineering

DEBOUNCE = 0.02     # s: moves closer together than this are answered once


def _decimals(step: float) -> int:
    return max(0, -int(f"{step:e}".split("e")[1]))


class Explorer:
    """One explorer app: the base scene, its session (store in `folder`) and the page."""

    def __init__(self, scene: Scene, folder: Path, store: Path | None = None, name: str = "taxel-explore",
                 front: Front | None = None):
        self.base, self.folder, self.front = scene, Path(folder), front
        self.server = get_server(name, client_type="vue3")
        self.state, self.ctrl = self.server.state, self.server.controller
        self.session = S.Session(store if store is not None else self.folder / "store")
        self.solver = ThreadPoolExecutor(1, thread_name_prefix="explore-2d")     # the numbers
        self.extras = ThreadPoolExecutor(1, thread_name_prefix="explore-extra")  # figures on request
        self.plots = ThreadPoolExecutor(1, thread_name_prefix="explore-front")   # the front with the design
        self.generation = 0
        self._updating: asyncio.Task | None = None      # the one update loop (at most one solve queued)
        self.job3d: S.Job3D | None = None
        self.scene: Scene | None = None
        self._init_state(ControlValues.of(scene))
        self._build()
        keys = [f"t_{n.name}" for n in NUMBERS] + ["piezo", "load", "law", "model", "readout"]
        self.state.change(*keys)(self._changed)

    # -- state ---------------------------------------------------------------------------------
    def _init_state(self, d: ControlValues):
        st = self.state
        for n in NUMBERS:
            st[f"t_{n.name}"] = d.numbers[n.name]
            st[f"x_{n.name}"] = float(d.numbers[n.name])
            st[f"e_{n.name}"] = []
        st.update({"piezo": d.piezo, "load": d.load, "law": d.law, "model": d.model, "readout": d.readout,
                   "e_piezo": [], "message": "", "voltage": "", "answer_model": "", "answer_time": "",
                   "bars": [], "crosstalk": "", "note": "", "busy": False, "answers": 0, "busy3d": False, "progress3d": "",
                   "answer3d": "", "figure": "", "figure_title": "", "error_lines": [], "extra_busy": False,
                   "export_name": self.base.name, "export_msg": "", "scene_name": self.base.name,
                   "has_front": self.front is not None, "front_image": "", "front_current": "", "send_msg": "",
                   "front_rows": self.front.rows() if self.front else [],
                   "front_note": (f"no control for {', '.join(self.front.unmatched)}: not loaded"
                                  if self.front and self.front.unmatched else "")})

    def design(self) -> ControlValues:
        st = self.state
        return ControlValues({n.name: str(st[f"t_{n.name}"]) for n in NUMBERS}, st.piezo, st.load, st.law,
                      st.model, st.readout)

    # -- updates -------------------------------------------------------------------------------
    def _changed(self, **_):
        self.generation += 1
        if self.job3d is not None and self.job3d.running():
            self.job3d.cancel()
            self.state.busy3d, self.state.progress3d = False, "3D solve cancelled: the design changed"
        if self._updating is None or self._updating.done():
            self._updating = asynchronous.create_task(self._update_loop())

    async def _update_loop(self):
        """Answer the newest design, once moves pause for DEBOUNCE: one solve at a time, and
        however many moves come in (every connection shares the design), one waiting: the newest."""
        while True:
            gen = self.generation
            await asyncio.sleep(DEBOUNCE)
            if gen != self.generation:
                continue
            await self._update(gen)
            if gen == self.generation:
                return

    async def _update(self, gen: int):
        st = self.state
        try:
            scene = scene_of(self.base, self.design())
            S.check_fits(scene)
        except S.TooLarge as exc:
            with st:
                st.message, st.busy = str(exc), False
            return
        except Exception as exc:                       # a value no control makes (a crafted message)
            if not isinstance(exc, FieldError):
                exc = FieldError(f"refused: {str(exc).splitlines()[0] if str(exc) else type(exc).__name__}", None)
            with st:
                for n in NUMBERS:
                    st[f"e_{n.name}"] = [str(exc)] if exc.field == n.name else []
                st.e_piezo = [str(exc)] if exc.field == "piezo" else []
                st.message = "" if exc.field in {n.name for n in NUMBERS} | {"piezo"} else str(exc)
            return
        with st:
            for n in NUMBERS:
                st[f"e_{n.name}"] = []
            st.e_piezo, st.message, st.busy = [], "", True

        def work():
            return self.session.answer(scene) if gen == self.generation else None
        try:
            ans = await asyncio.get_running_loop().run_in_executor(self.solver, work)
        except Exception as exc:                       # a failed solve: its one line, the app goes on
            with st:
                st.message, st.busy = f"the solve failed: {str(exc).splitlines()[0]}", False
            return
        if ans is None or gen != self.generation:
            return
        self.scene = scene
        with st:
            self._show(ans)
            st.busy = False
            st.answers += 1                            # answers shown (the load benchmark waits on it)
        if self.front is not None:
            await self._plot_front(ans, scene, gen)

    def _show(self, a: S.Answer):
        st = self.state
        v = a.pressed_voltage
        st.voltage = engineering(v, "V") if v is not None else "-"
        st.answer_model = a.model
        st.answer_time = ("from the store" if a.cached else "solved") + f" in {a.seconds * 1e3:.0f} ms"
        top = max((abs(x) for x in a.voltages.values()), default=1.0) or 1.0
        st.bars = [{"name": k, "text": engineering(x, "V"), "width": f"{100 * abs(x) / top:.1f}%",
                    "colour": "#c0392b" if x < 0 else "#2e86c1"} for k, x in a.voltages.items()]
        st.crosstalk = f"{100 * a.crosstalk:.1f} %" if a.crosstalk is not None else "- (one taxel)"
        st.note = a.note

    # -- the optimization's front -------------------------------------------------------------------
    async def _plot_front(self, a: S.Answer, scene: Scene, gen: int):
        v, f = a.pressed_voltage, scene.load.force
        current = (abs(v) / f, a.crosstalk) if v is not None and f and a.crosstalk is not None else None
        url = await asyncio.get_running_loop().run_in_executor(self.plots, self.front.image, current)
        if gen == self.generation:
            with self.state:
                self.state.front_image = url
                self.state.front_current = ("current design (the star): -" if current is None else
                                            f"current design (the star): {current[0]:.4g} V/N, "
                                            f"{100 * current[1]:.2f} %")

    def load_front(self, i: int):
        """Put front design `i`'s variables into the controls (the change solves it)."""
        if self.front is None or not isinstance(i, int) or not 0 <= i < len(self.front.designs):
            self.state.send_msg = f"no front design {str(i)[:20]!r}"
            return
        d = self.front.designs[i]
        with self.state:
            for name, value in d.values.items():
                self.state[f"t_{name}"] = f"{value:.6g}"
                self.state[f"x_{name}"] = float(value)
            self.state.send_msg = f"loaded the front design {d.label}"

    def send_to_optimization(self):
        """Write the current design as a scene TOML and an optimization TOML starting at it."""
        from taxel.studies.measured.calibrate import toml_text
        if self.front is None:
            return
        self.export()
        if not str(self.state.export_msg).startswith("wrote "):
            self.state.send_msg = self.state.export_msg
            return
        scene_path = Path(str(self.state.export_msg).removeprefix("wrote "))
        values = {n.name: n.value(self.scene) for n in NUMBERS if n.name != "offset"}
        data = self.front.optimization_data(values, scene_path.name)
        path = scene_path.with_name(f"{scene_path.stem}-optimization.toml")
        path.write_text(f"# written by taxel explore: {self.front.result.name} starting at the design "
                        f"{scene_path.name}\n" + toml_text(data))
        self.state.send_msg = f"wrote {path.resolve()}"

    # -- 3D --------------------------------------------------------------------------------------
    def solve_3d(self):
        if self.scene is None or self.job3d is not None and self.job3d.running():
            return                                       # one 3D solve at a time
        try:
            self.job3d = job = self.session.start_3d(self.scene)
        except (S.TooLarge, ValueError) as exc:          # refused before it starts, with its size
            self.state.busy3d, self.state.progress3d, self.state.answer3d = False, str(exc).splitlines()[0], ""
            return
        self.state.busy3d, self.state.progress3d, self.state.answer3d = True, "3D solve started (coarse mesh)", ""
        asynchronous.create_task(self._watch_3d(job))

    async def _watch_3d(self, job: S.Job3D):
        st = self.state
        while job.running():
            with st:
                st.progress3d = f"3D solve running (coarse mesh): {job.elapsed:.1f} s"
            await asyncio.sleep(0.25)
        if job.cancelled:
            return
        try:
            a = job.result()
            text = (f"3D: {engineering(a.pressed_voltage, 'V')} ({a.model}, coarse mesh, "
                    f"{a.seconds:.1f} s)")
        except RuntimeError as exc:
            text = f"3D solve failed: {exc}"
        with st:
            st.busy3d, st.progress3d, st.answer3d = False, "3D solve done", text

    # -- figures on request ----------------------------------------------------------------------
    def _extra(self, title: str, fn):
        scene = self.scene
        if scene is None or self.state.extra_busy:
            return
        self.state.extra_busy, self.state.figure_title = True, f"{title}: working..."

        async def run():
            try:
                out = await asyncio.get_running_loop().run_in_executor(self.extras, fn, scene)
                msg = title
            except Exception as exc:
                out, msg = None, f"{title} failed: {str(exc).splitlines()[0]}"
            with self.state:
                if isinstance(out, list):
                    self.state.error_lines = out
                elif out is not None:
                    self.state.figure = out
                self.state.figure_title, self.state.extra_busy = msg, False
        asynchronous.create_task(run())

    def section(self):
        if self.scene is not None and self.scene.model.type == "3d":
            return
        self._extra("deformed section, coloured by potential", S.section_image)

    def error_estimate(self):
        self._extra("error estimate of the current model", S.error_lines)

    def frequency(self):
        self._extra("frequency response through the readout", S.frequency_image)

    def force_curve(self):
        def curve(scene):
            f = scene.load.force or 1.0
            sess = S.Session(self.session.folder)          # this worker thread's own store connection
            try:
                pts = sess.force_curve(scene, [f * k / 5 for k in range(1, 6)])
            finally:
                sess.close()
            return S.curve_image(pts, f"{self.state.load} load: pressed-taxel voltage")
        self._extra("voltage-force curve", curve)

    # -- export ----------------------------------------------------------------------------------
    def export(self):
        from taxel.schema import NAME
        from taxel.studies.measured.calibrate import toml_text
        name = str(self.state.export_name).strip()
        if not NAME.fullmatch(name):
            self.state.export_msg = (f"{name!r} is not a file name: use letters, digits, '.', '_', '+' or '-'")
            return
        if self.scene is None:
            self.state.export_msg = "no valid design to save yet"
            return
        path = self.folder / "exports" / f"{name}.toml"
        path.parent.mkdir(parents=True, exist_ok=True)
        data = to_data(self.scene)
        data["name"] = name
        path.write_text(f"# saved by taxel explore from {self.base.name}\n" + toml_text(data))
        self.state.export_msg = f"wrote {path.resolve()}"

    # -- page ------------------------------------------------------------------------------------
    def _build(self):
        with SinglePageLayout(self.server) as layout:
            layout.title.set_text(f"taxel explore: {self.base.name}")
            with layout.content:
                with v3.VContainer(fluid=True):
                    with v3.VRow():
                        with v3.VCol(cols=5):
                            self._controls()
                        with v3.VCol(cols=7):
                            self._views()

    def _controls(self):
        for n in NUMBERS:
            dec = _decimals(n.step)
            with v3.VRow(dense=True, classes="align-center"):
                with v3.VCol(cols=7):
                    v3.VSlider(v_model=(f"x_{n.name}",), min=n.low, max=n.high, step=n.step,
                               label=n.label, hide_details=True, density="compact", id=f"slider_{n.name}",
                               update_modelValue=f"t_{n.name} = Number($event).toFixed({dec})",
                               disabled=("load == 'pressure'",) if n.name == "offset" else False)
                with v3.VCol(cols=5):
                    v3.VTextField(v_model=(f"t_{n.name}",), suffix=n.unit, density="compact",
                                  error_messages=(f"e_{n.name}",), id=f"field_{n.name}",
                                  update_modelValue=(f"x_{n.name} = isNaN(parseFloat($event)) ? x_{n.name}"
                                                     " : parseFloat($event)"))
        v3.VSelect(v_model=("piezo",), items=("piezos", piezo_names()), label="piezo material",
                   density="compact", error_messages=("e_piezo",))
        v3.VSelect(v_model=("load",), items=("loads", list(LOADS)), label="load kind", density="compact")
        v3.VSelect(v_model=("law",), items=("laws", LAWS), label="silicone law", density="compact")
        v3.VSelect(v_model=("model",), items=("models", list(MODELS)), label="model", density="compact")
        v3.VSelect(v_model=("readout",), items=("readouts", READOUTS), label="readout", density="compact")
        with v3.VRow(dense=True, classes="align-center"):
            v3.VTextField(v_model=("export_name",), label="save as (scene name)", density="compact")
            v3.VBtn("save scene TOML", click=self.export, id="export")
        html.Div("{{ export_msg }}", id="export_msg", classes="text-caption")

    def _front_card(self):
        with v3.VCard(classes="pa-3 mb-2", v_if=("has_front",)):
            html.Div("the optimization's front (stored; the star is the current design)", classes="text-subtitle-2")
            html.Img(src=("front_image",), v_show=("front_image",), style="max-width:100%", id="front_image")
            html.Div("{{ front_current }}", id="front_current", classes="text-caption")
            with html.Table(style="font-size:12px;width:100%", id="front_table"):
                with html.Tr(v_for="r in front_rows", key="r.i", id=("'front_row_' + r.i",),
                             click=(self.load_front, "[r.i]"), style="cursor:pointer"):
                    html.Td("{{ r.label }}")
                    html.Td("{{ r.sensitivity }}")
                    html.Td("{{ r.crosstalk }}")
                    html.Td("{{ r.design }}")
            html.Div("{{ front_note }}", classes="text-caption")
            v3.VBtn("send to a new optimization", click=self.send_to_optimization, id="send", classes="ma-1")
            html.Div("{{ send_msg }}", id="send_msg", classes="text-caption")

    def _views(self):
        self._front_card()
        with v3.VCard(classes="pa-3 mb-2"):
            html.Div("pressed-taxel open-circuit voltage", classes="text-subtitle-2")
            html.Div("{{ voltage }}", id="voltage", classes="text-h3")
            html.Div("{{ answer_model }}, {{ answer_time }}", id="answer_model", classes="text-caption")
            html.Div("{{ message }}", id="message", classes="text-error")
            html.Div("{{ answers }}:{{ busy }}", id="answers", style="display:none")
            html.Div("{{ note }}", classes="text-caption")
            v3.VProgressLinear(indeterminate=True, v_show=("busy",), height=2)
        with v3.VCard(classes="pa-3 mb-2"):
            html.Div("taxel voltages", classes="text-subtitle-2")
            with html.Div(v_for="b in bars", key="b.name", style="display:flex;align-items:center"):
                html.Div("{{ b.name }}", style="width:7em;font-size:12px")
                html.Div(style=("{width: b.width, background: b.colour, height: '12px', maxWidth: '60%'}",))
                html.Div("{{ b.text }}", style="margin-left:6px;font-size:12px")
            html.Div("crosstalk: {{ crosstalk }}", id="crosstalk", classes="text-caption")
        with v3.VCard(classes="pa-3 mb-2"):
            with v3.VRow(dense=True):
                v3.VBtn("solve in 3D", click=self.solve_3d, id="solve3d", disabled=("busy3d",), classes="ma-1")
                v3.VBtn("section", click=self.section, classes="ma-1", id="section")
                v3.VBtn("error estimate", click=self.error_estimate, classes="ma-1", id="estimate")
                v3.VBtn("frequency response", click=self.frequency, classes="ma-1", id="frequency")
                v3.VBtn("voltage-force curve", click=self.force_curve, classes="ma-1", id="curve",
                        disabled=("load == 'pressure'",))
            v3.VProgressLinear(indeterminate=True, v_show=("busy3d",), height=4, id="progress3d_bar")
            html.Div("{{ progress3d }}", id="progress3d", classes="text-caption")
            html.Div("{{ answer3d }}", id="answer3d", classes="text-body-1")
        with v3.VCard(classes="pa-3"):
            html.Div("{{ figure_title }}", id="figure_title", classes="text-subtitle-2")
            html.Div("{{ line }}", v_for="line in error_lines", id="error_lines",
                     style="white-space:pre;font-family:monospace;font-size:12px")
            html.Img(src=("figure",), v_show=("figure",), style="max-width:100%", id="figure")

    # -- serving ---------------------------------------------------------------------------------
    def serve(self, host: str = "127.0.0.1", port: int = 8080, token: str | None = None):
        """Serve the page until interrupted; prints the address (with the token) when ready.
        Every request and the WebSocket pass taxel.explore.guard (token, Host, Origin)."""
        from taxel.explore.guard import Guard, check_bind
        check_bind(host, token)
        guard = Guard(host, port, token)

        @self.ctrl.add("on_server_bind")
        def bind(wslink_server):
            wslink_server.app.middlewares.insert(0, guard.middleware())

        @self.ctrl.add("on_server_ready")
        def ready(**_):
            self._changed()                              # the first answer
            print(f"taxel explore: serving {self.base.name} at {guard.url()}", flush=True)
        self.server.start(host=host, port=port, open_browser=False, show_connection_info=False)
