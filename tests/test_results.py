"""The one result protocol: every analysis result has record(), summary(),
to_folder(), error and outputs(); a folder's result.json reads back into the same
type with the same record and outputs; an old-key result.json reads with a warning."""

import json
import math
import warnings

import numpy as np
import pytest

import taxel
from taxel.analyses import (FrequencyResult, LumpedResult, ResultError, StaticResult, TransientResult,
                            lumped_response, read, solve)
from taxel.analyses.results import MEMBERS, AnalysisResult

COARSE = {"mesh.size": "1 mm"}


def _close(a, b, path="record"):
    """Nested JSON-ready values equal, floats to 1e-9 relative (phase and magnitude
    of a complex output go through exp and back)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), (path, set(a) ^ set(b))
        for k in a:
            _close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, (list, tuple)):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _close(x, y, f"{path}[{i}]")
    elif isinstance(a, float) and isinstance(b, (int, float)):
        assert math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-9 * (abs(a) + 1e-30)) or (
            "phase" in path and math.isclose(abs(a - b) % 360, 0, abs_tol=1e-6)), (path, a, b)
    else:
        assert a == b, (path, a, b)


def _scenes():
    return {
        "static": lambda: solve(taxel.load("thesis-pzt-3x3-2d").replace(**COARSE)),
        "frequency": lambda: solve(taxel.load("thesis-pzt-frequency").replace(**COARSE, **{"analysis.points": 6})),
        "transient": lambda: solve(taxel.load("thesis-pzt-step").replace(**COARSE, **{"analysis.duration": 0.02})),
        "lumped": lambda: lumped_response(taxel.load("thesis-pzt-frequency").replace(**{"analysis.points": 6})),
    }


TYPES = {"static": StaticResult, "frequency": FrequencyResult, "transient": TransientResult, "lumped": LumpedResult}


@pytest.mark.parametrize("kind", list(TYPES))
def test_result_json_round_trip(kind, tmp_path):
    res = _scenes()[kind]()
    assert isinstance(res, TYPES[kind]) and res.kind == kind
    files = res.to_folder(tmp_path / kind)
    names = {p.name for p in files}
    assert {"result.json", "scene.json"} <= names
    assert any(n.endswith(".csv") for n in names) == (kind != "static")      # a static result without a press: none
    rec = json.loads((tmp_path / kind / "result.json").read_text())
    assert rec["kind"] == kind and rec["format"] >= 1
    assert rec["error_estimate"] is None and rec["error_note"].startswith("not estimated")
    back = read(tmp_path / kind)
    assert type(back) is type(res)
    _close(res.record(), back.record())
    _close(res.outputs(), back.outputs())
    assert back.summary()[1:] == res.summary()[1:] and str(back).splitlines() == back.summary()
    assert res.outputs() and all(isinstance(v, float) for v in res.outputs().values())


def test_static_outputs_are_named_by_the_vocabulary():
    res = _scenes()["static"]()
    out = res.outputs()
    assert set(out) == {"sensitivity", "charge_sensitivity", "pressed_voltage", "crosstalk", "max_strain"}
    e = res.electrodes[res.pressed]
    assert out["pressed_voltage"] == e.voltage
    assert out["sensitivity"] == pytest.approx(e.voltage / abs(res.applied_force))
    assert out["crosstalk"] == res.crosstalk and out["max_strain"] == res.max_strain


def test_read_back_has_no_mesh_or_fields(tmp_path):
    res = _scenes()["static"]()
    assert res.mesh is not None
    res.to_folder(tmp_path)
    back = read(tmp_path)
    assert back.mesh is None and back.fields is None
    assert back.voltages() == res.voltages() and np.array_equal(back.reaction, res.reaction)


def test_every_result_type_has_the_five_protocol_members():
    assert MEMBERS == ("record", "summary", "to_folder", "error", "outputs")
    for cls in TYPES.values():
        for m in MEMBERS:
            assert m in cls.__dataclass_fields__ or callable(getattr(cls, m, None)), (cls.__name__, m)
        assert "error" in cls.__dataclass_fields__ and cls.__dataclass_fields__["error"].default is None
    assert isinstance(_scenes()["lumped"](), AnalysisResult)


def test_a_result_json_without_its_kind_is_refused_in_one_line(tmp_path):
    """Nothing was released: a result.json taxel did not write (no "kind") is refused, not guessed."""
    res = _scenes()["static"]()
    res.to_folder(tmp_path)
    rec = json.loads((tmp_path / "result.json").read_text())
    rec.pop("kind")
    (tmp_path / "result.json").write_text(json.dumps(rec))
    with pytest.raises(ResultError, match="kind") as e:
        read(tmp_path)
    assert "\n" not in str(e.value)


def test_an_unknown_output_name_in_a_scene_is_refused():
    with pytest.raises(taxel.SceneError, match="voltage_per_newton"):
        taxel.load("thesis-pzt-single-2d").replace(**{"model.outputs": ("voltage_per_newton",)})


def test_a_folder_without_a_result_is_one_line(tmp_path):
    with pytest.raises(ResultError, match="result.json: no such file"):
        read(tmp_path)
    (tmp_path / "result.json").write_text('{"kind": "sculpture"}')
    with pytest.raises(ResultError, match="kind = 'sculpture'"):
        read(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        (tmp_path / "result.json").write_text("[1, 2]")
        with pytest.raises(ResultError, match="not a JSON object"):
            read(tmp_path)


def test_tidy_rows_name_columns_by_the_vocabulary_and_read_old_rows(tmp_path):
    from taxel.studies.store import Store, tidy_rows
    store = Store(tmp_path)
    old = {"voltage": {"taxel_0_0": -0.4}, "pressed": "taxel_0_0", "force": 0.5, "max_strain": 0.1, "seconds": 1.0}
    store.put("old", {"force": "0.5 N"}, "done", old)
    store.put("new", {"force": "1 N"}, "done", {**old, "force": 1.0, "outputs": {
        "pressed_voltage": -0.8, "sensitivity": -0.8, "max_strain": 0.2}})
    store.close()
    rows = {r["force"]: r for r in tidy_rows(tmp_path)}
    assert rows["0.5 N"]["pressed_voltage"] == -0.4 and rows["0.5 N"]["sensitivity"] == pytest.approx(-0.8)
    assert rows["1 N"]["pressed_voltage"] == -0.8 and rows["1 N"]["sensitivity"] == -0.8
    assert not any(k.endswith("_pressed") for r in rows.values() for k in r)      # the old column name is gone
