"""The explorer's controls: the design variables of a scene, with unit and range.

A numeric control is a slider plus a text field in a display unit (mm, um, N).
The slider's range is a convenience for the hand; what is accepted is what the
scene schema accepts: a typed value is applied to the scene as a string with its
unit ("0.8 mm") through `Scene.replace`, so a refused value gives the same one-line
SceneError as the same value in a scene file given to `taxel solve`.
"""

from __future__ import annotations

from dataclasses import dataclass

from taxel.scene import Scene, SceneError

# load kinds as the explorer names them -> the scene's [load] table
LOADS = {
    "pressure": {"kind": "taxel", "contact": False},
    "probe": {"kind": "probe", "contact": True, "shape": "flat", "radius": "1 mm"},
    "sphere": {"kind": "probe", "contact": True, "shape": "sphere", "radius": "5 mm"},
}
MODELS = {"2D": "plane_strain", "axisymmetric": "axisymmetric"}   # 3D: on demand, a button
LAWS = ["linear", "yeoh", "auto"]
READOUTS = ["open", "resistor", "charge_amplifier"]


@dataclass(frozen=True)
class Number:
    """A numeric design variable: `path` in the scene, shown in `unit` (`scale` SI
    units per display unit), a slider from `low` to `high` in steps of `step`."""

    name: str           # the page's state key
    path: str           # dotted scene path
    label: str
    unit: str
    scale: float
    low: float
    high: float
    step: float

    def value(self, scene: Scene) -> float:
        """The scene's value in the display unit."""
        node = scene
        for k in self.path.split("."):
            node = getattr(node, k)
        return round(float(node[0] if isinstance(node, tuple) else node) / self.scale, 6)

    def text(self, typed) -> str:
        """A typed value as a quantity string: a bare number gets the display unit."""
        s = str(typed).strip()
        try:
            float(s)
        except ValueError:
            return s
        return f"{s} {self.unit}"


NUMBERS = [
    Number("silicone_above", "array.silicone_above", "silicone above", "mm", 1e-3, 0.0, 5.0, 0.05),
    Number("silicone_below", "array.silicone_below", "silicone below", "mm", 1e-3, 0.0, 5.0, 0.05),
    Number("gap", "array.gap", "gap (edge to edge)", "mm", 1e-3, 0.5, 10.0, 0.1),
    Number("taxel_width", "array.taxel_width", "taxel width", "mm", 1e-3, 0.5, 10.0, 0.1),
    Number("piezo_thickness", "array.piezo_thickness", "piezo thickness", "um", 1e-6, 9.0, 1000.0, 1.0),
    Number("force", "load.force", "force", "N", 1.0, 0.05, 5.0, 0.05),
    Number("offset", "load.offset", "probe position (from the taxel centre)", "mm", 1e-3, -5.0, 5.0, 0.1),
]


def piezo_names() -> list[str]:
    """The piezo materials of the library (taxel.fem.constitution)."""
    from taxel.fem.constitution import Piezo, library
    return [m.name for m in library().values() if isinstance(m, Piezo)]


@dataclass(frozen=True)
class ControlValues:
    """What the controls say: the typed numbers (text, display unit) and the choices."""

    numbers: dict[str, str]
    piezo: str
    load: str = "pressure"
    law: str = "linear"
    model: str = "2D"
    readout: str = "open"

    def key(self) -> tuple:
        """The design as a hashable key (the explorer's memory of recent answers)."""
        return (tuple(sorted(self.numbers.items())), self.piezo, self.load, self.law, self.model, self.readout)

    @classmethod
    def of(cls, scene: Scene) -> ControlValues:
        """The controls' values of a scene (an array scene)."""
        load = "pressure" if scene.load.kind != "probe" else ("sphere" if scene.load.shape == "sphere"
                                                                  else "probe")
        model = "axisymmetric" if scene.model.type == "axisymmetric" else "2D"
        return cls({n.name: f"{n.value(scene):g}" for n in NUMBERS}, scene.array.piezo, load,
                   scene.model.silicone, model, scene.readout.circuit)


class FieldError(SceneError):
    """A refused value: the one-line message and the control (state key) it belongs to."""

    def __init__(self, message: str, field: str | None):
        super().__init__(message)
        self.field = field


def scene_of(base: Scene, design: ControlValues) -> Scene:
    """The base scene with the design applied (a validated Scene). Raises FieldError
    carrying the scene's one-line message and the control it names."""
    if base.array is None:
        raise FieldError("the explorer needs an [array] scene (a plate scene has no taxel controls)", None)
    for key, allowed in (("load", LOADS), ("model", MODELS), ("law", LAWS), ("readout", READOUTS)):
        if getattr(design, key) not in allowed:
            raise FieldError(f"{key}: {getattr(design, key)!r} is not one of {', '.join(allowed)}", key)
    changes: dict = {"load": dict(LOADS[design.load]), "model.type": MODELS[design.model],
                     "model.silicone": design.law, "readout.circuit": design.readout,
                     "array.piezo": design.piezo}
    if design.model == "axisymmetric":
        changes |= {"array.rows": 1, "array.cols": 1, "load.taxel": [0, 0]}
    for n in NUMBERS:
        text = n.text(design.numbers.get(n.name, ""))
        if n.name == "offset":
            if design.load == "pressure":
                continue
            changes["load.offset"] = [text, "0 m"]
        else:
            changes[n.path] = text
    try:
        scene = base.replace(**changes)
        from taxel import analyses
        analyses.check(scene)                      # the materials, as `taxel solve` checks them
    except (SceneError, KeyError, ValueError) as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) else str(exc)
        field = next((n.name for n in NUMBERS if msg.startswith(n.path)), None)
        if field is None and "material" in msg:
            field = "piezo"
        raise FieldError(msg, field) from None
    return scene
