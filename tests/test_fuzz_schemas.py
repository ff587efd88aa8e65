"""Property-based fuzzing of the four TOML schemas (scene, study, optimization,
rig) with hypothesis, through the command line in-process (`taxel.cli.main`).

Every generated document must end one of three ways: it validates and the command
completes (exit 0; a scene is solved on a coarse 2D mesh); it is refused with one
line "taxel: error: ..." (exit 2); or, valid but unsolvable, one line "taxel:
failed: ..." (exit 1). Never a traceback, never "internal error", never more than
one line.

Documents are a coarse, valid base mutated at random: known keys (every leaf of
the schema) and unknown ones, set to values drawn from the quantities, names and
literals a person types plus arbitrary TOML values (integers, floats with inf and
nan, booleans, strings, arrays, inline tables). The keys that only change cost
(model type, mesh sizes, sweep points) take values from a bounded set, so that a
valid scene stays a coarse 2D solve. Example counts: 300 scenes, 200 studies,
100 optimizations, 300 rigs a run (about 15 s in all on one core; times
TAXEL_FUZZ_SCALE); each is bounded by `max_examples` and has no deadline.
Failures found are kept as explicit `@example`s.
"""

from __future__ import annotations

import contextlib
import copy
import io
import math
import os
import tempfile
import typing
from pathlib import Path

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, example, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from pydantic import BaseModel  # noqa: E402

from taxel.cli import main  # noqa: E402
from taxel.scene import Scene  # noqa: E402

# examples per run; TAXEL_FUZZ_SCALE=10 multiplies them for a deeper run by hand or at night
SCALE = max(1, int(os.environ.get("TAXEL_FUZZ_SCALE", "1")))
SCENE_EXAMPLES, STUDY_EXAMPLES, OPT_EXAMPLES, RIG_EXAMPLES = (n * SCALE for n in (300, 200, 100, 300))
SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
                derandomize=False, database=None)


# ----------------------------------------------------------------------------- TOML text
def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf") if math.isinf(v) else repr(v)
    if isinstance(v, str):
        return toml_string(v)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{toml_string(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(v)


def toml_string(s: str) -> str:
    """A TOML basic string: quote, backslash and control characters escaped, the rest as is."""
    return '"' + "".join("\\" + c if c in '"\\' else f"\\u{ord(c):04x}" if ord(c) < 0x20 or ord(c) == 0x7F
                         else c for c in s) + '"'


def toml_doc(d: dict) -> str:
    """Top-level scalars, then one [table] per dict, then [[array]] tables of lists of dicts."""
    lines, tables, arrays = [], [], []
    for k, v in d.items():
        if isinstance(v, dict) and v:
            tables.append((k, v))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            arrays.append((k, v))
        else:
            lines.append(f"{toml_string(k)} = {toml_value(v)}")
    for k, v in tables:
        lines.append(f"[{toml_string(k)}]")
        lines += [f"{toml_string(a)} = {toml_value(b)}" for a, b in v.items()]
    for k, items in arrays:
        for item in items:
            lines.append(f"[[{toml_string(k)}]]")
            lines += [f"{toml_string(a)} = {toml_value(b)}" for a, b in item.items()]
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------- values
TYPED = ["1 mm", "0.5 mm", "3 mm", "-1 mm", "0 mm", "1 nm", "1e300 m", "inf mm", "nan mm", "1 N", "0.2 N", "-1 N",
         "0 N", "10 kPa", "1 %", "0.02", "150 %", "2 Hz", "1 kHz", "1 ms", "1 s", "500 Mohm", "820 pF", "5 V",
         "abc", "", " ", "1 parsec", "PSI-5H4E", "PVDF", "Ecoflex-00-30", "unobtainium", "linear", "yeoh", "open",
         "ground", "short", "taxel", "probe", "pressure", "between", "flat", "round", "sphere", "cylinder",
         "up", "down", "bonded", "free", "rollers", "clamped", "simply_supported", "static", "log", "linear",
         "step", "impulse", "chirp", "csv", "fixed", "half", "quarter", "full", "auto", "sensitivity",
         "crosstalk", "charge_sensitivity", "voltage_per_newton", "resistor", "charge_amplifier", "../x", "a/b"]
scalars = st.one_of(st.sampled_from(TYPED), st.integers(-3, 20), st.integers(), st.booleans(),
                    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=6))
values = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                       st.dictionaries(st.text(max_size=5), inner, max_size=2)),
                      max_leaves=5)

# cost keys: a valid value stays a cheap coarse 2D solve
BOUNDED = {"model.type": ["plane_strain", "plane_stress", "axisymmetric", "three-d", 3],
           "model.fidelity": ["fixed", "best", 1], "analysis.type": ["static", "modal", 0],
           "analysis.points": [2, 5, 0, 10 ** 9, "many"], "mesh.size": ["1 mm", "2 mm", "-1 mm", "abc", 0],
           "mesh.piezo_size": ["0.25 mm", "0.5 mm", "5 mm", "0 mm", None], "mesh.order": [1, 2, 3, "2"],
           "mesh.piezo_layers": [1, 2, 0, 9, 1.5], "model.depth": ["4 mm", "-4 mm", "abc"],
           "array.rows": [1, 2, 0, 17, True], "array.cols": [1, 2, 3, 0, 17, "3"],
           "analysis.duration": ["1 s", "1e7 s", "-1 s"], "analysis.dt": ["0.5 ms", "1 us", "2 s"],
           "warm_touch.time": ["2 s", "1e7 s", "-1 s"], "warm_touch.dt": ["20 ms", "1 us", "2 s"]}


# values a person would type that the scene takes: most documents built from these solve
VALID = {"model.tolerance": ["1 %", "0.02", 0.05, "5 percent"], "model.silicone": ["linear", "yeoh"],
         "model.outputs": [["sensitivity"], ["sensitivity", "charge_sensitivity"]],
         "array.taxel_width": ["2 mm", "4 mm", "6 mm"], "array.piezo": ["PSI-5H4E", "PVDF"],
         "array.piezo_thickness": ["0.127 mm", "52 um"], "array.silicone_above": ["0.5 mm", "2 mm", "0 mm"],
         "array.silicone_below": ["0.5 mm", "2 mm"], "array.margin": ["1 mm", "5 mm"], "array.poling": ["down"],
         "load.force": ["0.2 N", "5 N", "-1 N"], "load.kind": ["taxel", "probe"], "load.radius": ["1 mm", "2 mm"],
         "load.profile": ["flat", "round"], "load.offset": [["0.5 mm", "0 mm"]],
         "supports.bottom": ["bonded", "rollers", "free"], "supports.edges": ["free", "clamped", "rollers"],
         "electrodes.taxel_0_0": ["open", "ground", "5 V"], "readout.circuit": ["open", "resistor"],
         "dynamics.silicone_loss": ["10 %", 0.2], "mesh.formulation": ["mixed", "displacement"],
         "warm_touch.finger": ["34 degC", "310 K", "5 V"], "warm_touch.duration": ["0.5 s", "5 s"]}


def leaves(model: type[BaseModel], prefix="") -> list[str]:
    out = []
    for name, field in model.model_fields.items():
        ann = field.annotation
        args = [a for a in typing.get_args(ann) if a is not type(None)] or [ann]
        sub = next((a for a in args if isinstance(a, type) and issubclass(a, BaseModel)), None)
        out += leaves(sub, f"{prefix}{name}.") if sub is not None and name != "plate" else [f"{prefix}{name}"]
    return out


SCENE_LEAVES = leaves(Scene)


def set_dotted(d: dict, path: str, value):
    keys = path.split(".")
    for k in keys[:-1]:
        nxt = d.get(k)
        if not isinstance(nxt, dict):
            nxt = d[k] = {}
        d = nxt
    if value is None:
        d.pop(keys[-1], None)
    else:
        d[keys[-1]] = value


@st.composite
def mutations(draw, known: list[str], bounded: dict, valid: dict | None = None):
    """0-4 (dotted path, value) changes: valid values of some keys, any value of known
    leaves (bounded for the cost keys), unknown keys."""
    out = []
    for _ in range(draw(st.integers(0, 4))):
        kind = draw(st.sampled_from(["valid", "valid", "known", "known", "unknown"] if valid else
                                    ["known", "known", "known", "unknown"]))
        if kind == "valid":
            path = draw(st.sampled_from(sorted(valid)))
            out.append((path, draw(st.sampled_from(valid[path]))))
            continue
        if kind == "known":
            path = draw(st.sampled_from(known))
            value = draw(st.sampled_from(bounded[path])) if path in bounded else \
                draw(st.one_of(st.sampled_from(TYPED), st.sampled_from(TYPED), values))
        else:
            path = draw(st.sampled_from(known)).rsplit(".", 1)[0] + "." + draw(st.text(min_size=1, max_size=6))
            value = draw(values)
        out.append((path, value))
    return out


# ----------------------------------------------------------------------------- the command line
def run(argv: list[str], files: dict[str, str]) -> tuple[int, str, str]:
    """`taxel ARGV` in-process in a fresh temporary folder: (exit code, stdout, stderr)."""
    with tempfile.TemporaryDirectory() as d:
        for name, text in files.items():
            Path(d, name).write_text(text, encoding="utf-8")
        here = os.getcwd()
        out, err = io.StringIO(), io.StringIO()
        os.chdir(d)
        try:
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                code = main(argv)
        finally:
            os.chdir(here)
    return code, out.getvalue(), err.getvalue()


def check(code: int, err: str, doc: str, unconverged_ok: bool = False):
    """The property: exit 0; or one line, "taxel: error:" with exit 2 or "taxel: failed:"
    with exit 1; with `unconverged_ok`, also exit 1 and nothing on stderr (an
    optimization that ran but did not converge: its summary is on stdout)."""
    lines = [x for x in err.splitlines() if x.strip()]
    assert "Traceback" not in err and "internal error" not in err, f"{err}\n--- document:\n{doc}"
    if code == 0 or (unconverged_ok and code == 1 and not lines):
        return
    assert len(lines) == 1, f"exit {code}, stderr {err!r}\n--- document:\n{doc}"
    assert (code, lines[0].split(":")[1].strip()) in ((2, "error"), (1, "failed")), f"{err!r}\n{doc}"


# ----------------------------------------------------------------------------- scenes
SCENE_BASE = {"model": {"type": "plane_strain"}, "mesh": {"size": "1 mm", "piezo_size": "0.5 mm"},
              "array": {"taxel_width": "4 mm"}, "load": {"force": "1 N"}}


@pytest.mark.slow
@settings(max_examples=SCENE_EXAMPLES, **SETTINGS)
@given(mutations(SCENE_LEAVES, BOUNDED, VALID))
@example([("model.tolerance", "1 %")])                                  # round three: percent strings
@example([("load.kind", "probe"), ("load.radius", "50 mm")])          # an indenter wider than the part
@example([("dynamics.silicone_loss", "10 %"), ("analysis.tolerance", "0.02")])
@example([("model.silicone", "yeoh"), ("array.silicone", "gel"),
          ("materials.gel", {"kind": "solid", "E": 1e5, "nu": 0.45, "rho": 1000})])
@example([("electrodes.taxel_0_0", [])])
def test_fuzzed_scenes_solve_or_fail_in_one_line(changes):
    data = copy.deepcopy(SCENE_BASE)
    for path, value in changes:
        set_dotted(data, path, value)
    doc = toml_doc(data)
    code, out, err = run(["solve", "s.toml"], {"s.toml": doc})
    check(code, err, doc)
    if code == 0:
        assert "applied force" in out or "voltage" in out


# ----------------------------------------------------------------------------- studies
STUDY_BASE = {"base": "thesis-pzt-single-2d", "outputs": ["voltage"],
              "overrides": {"mesh.size": "1 mm", "mesh.piezo_size": "0.5 mm"},
              "parameters": [{"path": "load.force", "values": ["0.2 N", "0.4 N"]}]}
STUDY_KEYS = ["name", "base", "sampling", "samples", "seed", "outputs", "description", "overrides.load.force",
              "overrides.model.tolerance", "overrides.array.gap", "parameters"]
PARAMETER = st.fixed_dictionaries(
    {"path": st.sampled_from(["load.force", "array.gap", "model.tolerance", "array.silicone_above", "lode.x",
                              "array", "", "dynamics.silicone_loss"])},
    optional={"values": st.lists(values, max_size=2), "start": values, "stop": values, "step": values,
              "num": st.sampled_from([2, 3, 1, 0, 10 ** 9]), "label": scalars, "labels": st.lists(scalars, max_size=2)})
STUDY_BOUNDED = {"samples": [1, 2, 3, 0, -1, 10 ** 9], "seed": [0, 1, -1, 2 ** 32, 1.5, "x"],
                 "sampling": ["grid", "lhs", "sobol"], "parameters": None}


@st.composite
def studies(draw):
    data = copy.deepcopy(STUDY_BASE)
    if draw(st.booleans()):
        data["parameters"] = draw(st.lists(PARAMETER, min_size=0, max_size=2))
    for path, value in draw(mutations([k for k in STUDY_KEYS if k != "parameters"],
                                      {k: v for k, v in STUDY_BOUNDED.items() if v is not None})):
        if path.startswith("overrides."):
            data["overrides"][path.removeprefix("overrides.")] = value
        else:
            set_dotted(data, path, value)
    return data


@pytest.mark.slow
@settings(max_examples=STUDY_EXAMPLES, **SETTINGS)
@given(studies())
@example({**STUDY_BASE, "sampling": "lhs", "samples": 2, "seed": -1,
          "parameters": [{"path": "load.force", "start": "0.2 N", "stop": "1 N"}]})
@example({**STUDY_BASE, "parameters": [{"path": "load.force", "values": ["0.2 N", "0.4 mm"]}]})
@example({**STUDY_BASE, "overrides": {"model.tolerance": "1 %", "mesh.size": "1 mm"}})
def test_fuzzed_studies_run_or_fail_in_one_line(data):
    doc = toml_doc(data)
    code, out, err = run(["study", "run", "st.toml", "--out", "o", "--workers", "1", "--quiet"], {"st.toml": doc})
    check(code, err, doc)


# ----------------------------------------------------------------------------- optimizations
OPT_BASE = {"base": "thesis-pzt-single-2d",
            "variables": {"above": {"path": "array.silicone_above", "min": "0.5 mm", "max": "1.5 mm"}},
            "objective": {"maximize": "sensitivity"}, "algorithm": {"max_evaluations": 2, "global": "none"}}
OPT_KEYS = ["name", "base", "reference", "noise", "variables.above.path", "variables.above.min",
            "variables.above.max", "variables.above.start", "variables.gap", "objective.maximize",
            "objective.minimize", "constraints.crosstalk", "constraints.total_thickness", "constraints.gap",
            "algorithm.local", "algorithm.xtol", "pareto.points"]
OPT_BOUNDED = {"variables.above.path": ["array.silicone_above", "array.silicone", "model.type", "array.rows",
                                        "array", "array.gap.x", "nope.x"],
               "constraints.crosstalk": ["<= 0.05", "<= 5 %", ">= abc", "= 1", 3],
               "constraints.total_thickness": ["<= 2 mm", "<= 1 um", ">= 2 N"],
               "pareto.points": [2, 1, 51]}


@pytest.mark.slow
@settings(max_examples=OPT_EXAMPLES, **SETTINGS)
@given(mutations(OPT_KEYS, OPT_BOUNDED))
@example([("variables.above.path", "array.silicone")])        # round three: a variable on a material name
@example([("algorithm.xtol", "2 %"), ("constraints.total_thickness", "<= 2 mm")])
def test_fuzzed_optimizations_run_or_fail_in_one_line(changes):
    data = copy.deepcopy(OPT_BASE)
    for path, value in changes:
        set_dotted(data, path, value)
    data["algorithm"]["max_evaluations"] = 2                   # bounded: at most two solves a run
    data["algorithm"]["global"] = "none"
    data.pop("pareto", None) if "pareto" in data and not isinstance(data["pareto"], dict) else None
    doc = toml_doc(data)
    code, out, err = run(["optimize", "op.toml", "--out", "o", "--workers", "1"], {"op.toml": doc})
    check(code, err, doc, unconverged_ok=True)
    if code == 1 and not err.strip():
        assert "written to" in out


# ----------------------------------------------------------------------------- rigs
RIG_BASE = {"name": "fuzz", "port": {"url": "loop://", "baud": 115200, "protocol": "taxel-cobs"},
            "sampling": {"rate": "2 kHz"}, "adc": {"bits": 16, "range": ["-10 V", "10 V"]},
            "channels": [{"index": 0, "name": "taxel_0_0", "gain": 1.0},
                         {"index": 1, "name": "force", "sensitivity": "0.5 V/N"}]}
RIG_KEYS = ["name", "port.url", "port.baud", "port.protocol", "sampling.rate", "adc.bits", "adc.range",
            "adc.offset", "conditioning.circuit", "conditioning.R", "conditioning.notch", "channels"]
CHANNEL = st.fixed_dictionaries({"index": st.sampled_from([0, 1, 2, 31, 32, -1, "0"]),
                                 "name": st.sampled_from(["taxel_0_0", "taxel_0_1", "force", "travel", "x", "taxel_a"])},
                                optional={"gain": st.sampled_from([1.0, "10", "1000 %", 0, -1, "1 mV", "x"]),
                                          "sensitivity": st.sampled_from(["0.5 V/N", "1 V/mm", "1 V", 0])})
RIG_BOUNDED = {"port.url": ["loop://", ""], "channels": None}


@st.composite
def rigs(draw):
    data = copy.deepcopy(RIG_BASE)
    if draw(st.booleans()):
        data["channels"] = draw(st.lists(CHANNEL, min_size=0, max_size=3))
    for path, value in draw(mutations([k for k in RIG_KEYS if k != "channels"],
                                      {k: v for k, v in RIG_BOUNDED.items() if v is not None})):
        set_dotted(data, path, value)
    return data


@pytest.mark.slow
@settings(max_examples=RIG_EXAMPLES, **SETTINGS)
@given(rigs())
@example({**RIG_BASE, "channels": [{"index": 0, "name": "taxel_0_0", "gain": "1000 %"}]})
@example({**RIG_BASE, "adc": {"bits": 16, "range": ["10 V", "-10 V"]}})
def test_fuzzed_rigs_capture_or_fail_in_one_line(data):
    doc = toml_doc(data)
    code, out, err = run(["measure", "capture", "rig.toml", "--url", "loop://", "--seconds", "0.05",
                          "--out", "m", "--quiet"], {"rig.toml": doc})
    check(code, err, doc)


def test_the_toml_writer_round_trips():
    import tomllib
    data = {"a": 1, "b": [1.5, "x"], "t": {"k": {"n": True}, "s": "é\n\x7f\"\\😀"}, "arr": [{"x": 1}, {"y": "2"}]}
    assert tomllib.loads(toml_doc(data)) == data
