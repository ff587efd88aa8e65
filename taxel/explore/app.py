"""The explorer's page (trame, pyvista's web backend; Vue 3 + Vuetify 3).

Every control is a slider and a text field in its display unit, or a choice.
Every page (a connection) has its own design (taxel.explore.tab: one tab's moves
never change another's); what a page may send is checked on the WebSocket first
(taxel.explore.wire) and every HTTP request by taxel.explore.guard. The explorer
holds what the pages share: the base scene, the study store (a design seen before,
by any page, is read, not solved) and the lanes the work runs in, off the event loop:

- the fast lane (FAST_WORKERS threads): reading a design and solving a small one
  (at most SMALL_UNKNOWNS unknowns, well under a second);
- the slow lane (one thread): a larger design (up to the 2D cap, session.MEMORY_2D
  of this machine's memory) and the figures on request (section, error estimate,
  frequency response, voltage-force curve), one at a time;
- 3D: one process at a time (session.Job3D, up to session.MEMORY_3D).

So the caps add up: the slow lane's solve, the 3D solve and the fast lane's small
solves together need at most session.MEMORY_BUDGET of this machine's memory.
"""

from __future__ import annotations

import copy
import dataclasses
import threading
from collections import OrderedDict
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from trame.app import get_server
from trame.ui.vuetify3 import SinglePageLayout
from trame.widgets import html
from trame.widgets import vuetify3 as v3

from taxel.explore import session as S
from taxel.explore.controls import (
    LAWS,
    LOADS,
    MODELS,
    NUMBERS,
    READOUTS,
    ControlValues,
    FieldError,
    piezo_names,
    scene_of,
)
from taxel.explore.front import Front
from taxel.explore.tab import Tab
from taxel.explore.wire import MAX_MESSAGE, Refusals, Wire
from taxel.scene import Scene
from taxel.schema import to_data

FAST_WORKERS = 2
RECENT = 256            # designs whose answers the explorer keeps in memory (a few kB each)


def _decimals(step: float) -> int:
    return max(0, -int(f"{step:e}".split("e")[1]))


@dataclass
class Lanes:
    """Where the explorer's work runs (module docstring)."""

    fast: ThreadPoolExecutor
    slow: ThreadPoolExecutor
    small: float = S.SMALL_UNKNOWNS


class Explorer:
    """One explorer app: the base scene, its store (in `folder`), the pages and their page."""

    def __init__(self, scene: Scene, folder: Path, store: Path | None = None, name: str = "taxel-explore",
                 front: Front | None = None):
        self.base, self.folder, self.front = scene, Path(folder), front
        self.server = get_server(name, client_type="vue3")
        self.server.options["ws_max_msg_size"] = MAX_MESSAGE     # aiohttp refuses a longer frame
        self.state, self.ctrl = self.server.state, self.server.controller
        self.store = store if store is not None else self.folder / "store"
        self.lanes = Lanes(ThreadPoolExecutor(FAST_WORKERS, thread_name_prefix="explore-fast"),
                           ThreadPoolExecutor(1, thread_name_prefix="explore-slow"))
        self._sessions = threading.local()              # one store connection per thread
        self.tabs: dict[str, Tab] = {}
        self._recent: OrderedDict = OrderedDict()      # design key -> (scene, answer): Explorer.recall
        self.refuse = Refusals()
        self.publish = lambda client, data: None        # set by Wire.install when the server binds
        self.initial = self._init_state(ControlValues.of(scene))
        self._build()
        self.triggers = {self.export: 0, self.load_front: 1, self.send_to_optimization: 0, self.solve_3d: 0,
                         self.section: 0, self.error_estimate: 0, self.frequency: 0, self.force_curve: 0}

    # -- state: the page's defaults; each page's own copy is its Tab's -------------------------------
    def _init_state(self, d: ControlValues) -> dict:
        st = {}
        for n in NUMBERS:
            st[f"t_{n.name}"] = d.numbers[n.name]
            st[f"x_{n.name}"] = float(d.numbers[n.name])
            st[f"e_{n.name}"] = []
        st.update({"piezo": d.piezo, "load": d.load, "law": d.law, "model": d.model, "readout": d.readout,
                   "e_piezo": [], "message": "", "voltage": "", "answer_model": "", "answer_time": "",
                   "bars": [], "crosstalk": "", "note": "", "busy": False, "answers": 0, "busy3d": False,
                   "progress3d": "", "answer3d": "", "figure": "", "figure_title": "", "error_lines": [],
                   "extra_busy": False, "export_name": self.base.name, "export_msg": "",
                   "scene_name": self.base.name, "front_image": "", "front_current": "", "send_msg": ""})
        self.state.update(st)
        self.state.update({"has_front": self.front is not None,
                           "front_rows": self.front.rows() if self.front else [],
                           "front_note": (f"no control for {', '.join(self.front.unmatched)}: not loaded"
                                          if self.front and self.front.unmatched else "")})
        return st

    # -- the pages (called by wire.Wire with the connection's id) --------------------------------------
    def tab(self, client: str) -> Tab:
        t = self.tabs.get(client)
        if t is None:
            t = self.tabs[client] = Tab(client, self, copy.deepcopy(self.initial))
            t.changed()                                  # its first answer
        return t

    def state_of(self, client: str) -> dict:
        from trame_server.utils import clean_state
        full = self.server.get_server_state()
        ok, _ = clean_state({**full["state"], **self.tab(client).state})
        return {**full, "state": ok}

    def update(self, client: str, changes: list[dict]) -> None:
        self.tab(client).apply(changes)

    def trigger(self, client: str, name, args: list) -> None:
        fn = self.ctrl.trigger_fn(name) if isinstance(name, str) else None
        if fn not in self.triggers:
            self.refuse(client, f"the trigger {str(name)[:40]!r}")
            return
        if len(args) != self.triggers[fn]:
            self.refuse(client, f"{fn.__name__}: {len(args)} arguments, expected {self.triggers[fn]}")
            return
        fn(self.tab(client), *args)

    def closed(self, client: str) -> None:
        t = self.tabs.pop(client, None)
        if t is not None:
            t.close()

    # -- work in the lanes (any thread) ---------------------------------------------------------------
    def session(self) -> S.Session:
        """This thread's session (a Store keeps its SQLite connection in its thread)."""
        if getattr(self._sessions, "s", None) is None:
            self._sessions.s = S.Session(self.store)
        return self._sessions.s

    def prepare(self, design: ControlValues) -> tuple[Scene, object]:
        """The design's scene and solve cost; FieldError (one line) where it is refused."""
        try:
            scene = scene_of(self.base, design)
            return scene, S.check_fits(scene, S.MEMORY_2D)
        except FieldError:
            raise
        except Exception as exc:                        # TooLarge, or a value no control makes
            raise FieldError(str(exc).splitlines()[0] if str(exc) else type(exc).__name__, None) from None

    def answer(self, scene: Scene) -> S.Answer:
        return self.session().answer(scene)

    def recall(self, design: ControlValues) -> tuple[Scene, S.Answer] | None:
        """A design answered lately (the last RECENT designs, any page's): its scene and
        answer, shown as from the store (0 ms); None otherwise. On the event loop only."""
        hit = self._recent.get(design.key())
        if hit is None:
            return None
        self._recent.move_to_end(design.key())
        return hit[0], dataclasses.replace(hit[1], seconds=0.0, cached=True)

    def remember(self, design: ControlValues, scene: Scene, answer: S.Answer) -> None:
        self._recent[design.key()] = (scene, answer)
        if len(self._recent) > RECENT:
            self._recent.popitem(last=False)

    # -- the optimization's front -------------------------------------------------------------------
    def load_front(self, tab: Tab, i):
        """Put front design `i`'s variables into the page's controls (the change solves it)."""
        if self.front is None or isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < len(self.front.designs):
            tab.push(send_msg=f"no front design {str(i)[:20]!r}")
            return
        d = self.front.designs[i]
        changes = {}
        for name, value in d.values.items():
            changes[f"t_{name}"], changes[f"x_{name}"] = f"{value:.6g}", float(value)
        tab.push(**changes, send_msg=f"loaded the front design {d.label}")
        tab.changed()

    def send_to_optimization(self, tab: Tab):
        """Write the page's design as a scene TOML and an optimization TOML starting at it."""
        from taxel.studies.measured.calibrate import toml_text
        if self.front is None:
            return
        path = self.export(tab)
        if path is None:
            tab.push(send_msg=tab.state["export_msg"])
            return
        values = {n.name: n.value(tab.scene) for n in NUMBERS if n.name != "offset"}
        data = self.front.optimization_data(values, path.name)
        out = path.with_name(f"{path.stem}-optimization.toml")
        out.write_text(f"# written by taxel explore: {self.front.result.name} starting at the design "
                       f"{path.name}\n" + toml_text(data))
        tab.push(send_msg=f"wrote {out.resolve()}")

    # -- 3D and figures: the page's own (tab.Tab) ---------------------------------------------------------
    def solve_3d(self, tab: Tab):
        tab.solve_3d()

    def section(self, tab: Tab):
        if tab.scene is not None and tab.scene.model.type == "3d":
            return
        tab.extra("deformed section, coloured by potential", S.section_image)

    def error_estimate(self, tab: Tab):
        tab.extra("error estimate of the current model", S.error_lines)

    def frequency(self, tab: Tab):
        tab.extra("frequency response through the readout", S.frequency_image)

    def force_curve(self, tab: Tab):
        load = tab.state["load"]

        def curve(scene):
            f = scene.load.force or 1.0
            pts = self.session().force_curve(scene, [f * k / 5 for k in range(1, 6)])
            return S.curve_image(pts, f"{load} load: pressed-taxel voltage")
        tab.extra("voltage-force curve", curve)

    # -- export ----------------------------------------------------------------------------------
    def export(self, tab: Tab) -> Path | None:
        """The page's design as a scene TOML under the output folder's exports/ (its path)."""
        from taxel.schema import NAME
        from taxel.studies.measured.calibrate import toml_text
        name = str(tab.state["export_name"]).strip()
        if not NAME.fullmatch(name):
            tab.push(export_msg=f"{name[:40]!r} is not a file name: use letters, digits, '.', '_', '+' or '-'")
            return None
        if tab.scene is None:
            tab.push(export_msg="no valid design to save yet")
            return None
        path = self.folder / "exports" / f"{name}.toml"
        path.parent.mkdir(parents=True, exist_ok=True)
        data = to_data(tab.scene)
        data["name"] = name
        path.write_text(f"# saved by taxel explore from {self.base.name}\n" + toml_text(data))
        tab.push(export_msg=f"wrote {path.resolve()}")
        return path

    # -- page ------------------------------------------------------------------------------------
    def _build(self):
        with SinglePageLayout(self.server) as layout:
            layout.title.set_text(f"taxel explore: {self.base.name}")
            with layout.content, v3.VContainer(fluid=True), v3.VRow():
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
        Every request passes taxel.explore.guard (token, Host, Origin), every WebSocket
        message taxel.explore.wire; the wslink secret is a new one of this run's (guard)."""
        from taxel.explore.guard import Guard, check_bind
        check_bind(host, token)
        guard = Guard(host, port, token)
        wire = Wire(self, self.refuse)

        @self.ctrl.add("on_server_bind")
        def bind(wslink_server):
            wslink_server.app.middlewares.insert(0, guard.middleware())
            for h in wslink_server._ws_handlers:
                h.serverProtocol.updateSecret(guard.secret)
            wire.install(wslink_server)

        @self.ctrl.add("on_server_ready")
        def ready(**_):
            # the base design into the store, so every page's first answer is read, not solved
            self.lanes.fast.submit(self._warm)
            print(f"taxel explore: serving {self.base.name} at {guard.url()}", flush=True)
        self.server.start(host=host, port=port, open_browser=False, show_connection_info=False)

    def _warm(self):
        try:
            self.answer(self.prepare(ControlValues.of(self.base))[0])
        except Exception:                                # the page shows the base design's refusal itself
            pass
