"""One solve that returns, one writer per result folder, one JSON record.

- `taxel.solve` of a press that stops short of its load returns its last converged
  state with `success` False and its `stop` (what was asked, what was reached, why);
- for every analysis, `result.to_folder(d)` writes the same files as
  `taxel solve SCENE --out d` (`taxel lumped` for the lumped model), with the same
  JSON up to the timings;
- `taxel solve SCENE --json` prints exactly one JSON record, whatever the analysis.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import taxel
from taxel.cli import EXIT_FAILED, main

EXAMPLES = Path(taxel.__file__).parent / "examples"

# every analysis a result folder is written for, as (command, example, text replaced in
# its TOML to keep it cheap)
CASES = {
    "static": ("solve", "thesis-pzt-single-2d", ()),
    "press": ("solve", "thesis-pzt-probe-2d", ()),
    "frequency": ("solve", "thesis-pzt-frequency", (('type = "frequency"', 'type = "frequency"\npoints = 8'),)),
    "transient": ("solve", "thesis-pzt-step", (('duration = "6 s"', 'duration = "0.02 s"'),)),
    "lumped": ("lumped", "thesis-pzt-frequency", (('type = "frequency"', 'type = "frequency"\npoints = 8'),)),
}
TIMINGS = {"times_s", "seconds"}
# a Yeoh silicone under the taxel's pressure patch, asked for 5 N, creases at the patch edge
# and its Newton stops short (coarse and P1 to be cheap)
YEOH_STOPS = (('type = "plane_strain"', 'type = "plane_strain"\nsilicone = "yeoh"'), ('size = "0.5 mm"', 'size = "1 mm"'),
              ("order = 2", "order = 1"), ('force = "1 N"', 'force = "5 N"'))


def scene_file(tmp_path: Path, name: str, changes) -> Path:
    text = (EXAMPLES / f"{name}.toml").read_text()
    for old, new in changes:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file()}


def untimed(path: Path) -> dict:
    return {k: v for k, v in json.loads(path.read_text()).items() if k not in TIMINGS}


def test_a_yeoh_patch_load_that_stops_returns_its_last_converged_state():
    """A Yeoh silicone under the taxel's pressure patch, asked for 5 N, creases at the
    patch edge and its Newton stops (coarse and P1 to be cheap): the result says so."""
    sc = taxel.load("thesis-pzt-single-2d").replace(**{"model.silicone": "yeoh", "load.force": 5.0,
                                                       "mesh.size": 1e-3, "mesh.order": 1})
    res = taxel.solve(sc)
    assert res.success is False
    st = res.stop
    assert st.requested == 5.0 and st.load == "force" and st.cause is None and "Newton" in st.message
    assert 0 < res.applied_force < 5.0 and res.scene.load.force == pytest.approx(res.applied_force)
    assert res.newton is not None and not res.newton.converged
    assert res.record()["stop"]["requested"] == 5.0
    assert any(line.startswith("STOPPED SHORT of load.force = 5 N") for line in res.summary())


@pytest.mark.slow
def test_a_press_that_stops_returns_its_last_converged_state():
    """The 2D probe example, frictionless, asked for 3 N, stops past 1.62 N
    (benchmarks/stopped_press.py): the result says so instead of raising."""
    sc = taxel.load("thesis-pzt-probe-2d").replace(**{"load.friction": "frictionless", "load.force": 3.0})
    res = taxel.solve(sc)
    assert res.success is False
    st = res.stop
    assert st.requested == 3.0 and st.load == "force" and st.unit == "N"
    assert st.cause in ("inversion", "stagnation") and st.message
    assert 1.0 < res.applied_force < 3.0
    assert res.scene.load.force == pytest.approx(res.applied_force)          # the load reached
    rec = res.record()
    assert rec["stop"]["requested"] == 3.0 and rec["stop"]["cause"] == st.cause


def test_a_solve_that_reaches_its_load_succeeds():
    res = taxel.solve("thesis-pzt-single-2d")
    assert res.success is True and res.stop is None and res.record()["stop"] is None


@pytest.mark.parametrize("case", list(CASES))
def test_to_folder_writes_what_the_command_leaves(case, tmp_path):
    command, name, changes = CASES[case]
    path = scene_file(tmp_path, name, changes)
    by_cli = tmp_path / "cli"
    assert main([command, str(path), "--out", str(by_cli)]) == 0
    res = taxel.solve(path) if command == "solve" else taxel.lumped(path)
    by_api = tmp_path / "api"
    written = res.to_folder(by_api)
    assert files(by_api) == files(by_cli) == {str(p.relative_to(by_api)) for p in written}
    assert {"result.json", "scene.json", "summary.txt"} <= files(by_api)
    assert any(f.endswith(".png") for f in files(by_api))
    assert any(f.endswith(".csv") for f in files(by_api)) == (case != "static")
    for f in files(by_api):
        if f.endswith(".json"):
            assert untimed(by_api / f) == untimed(by_cli / f), f


# a press's record is the static one (its --json is tested in test_contact_scene)
@pytest.mark.parametrize("case", [c for c in CASES if c != "press"])
def test_json_prints_one_record(case, tmp_path, capsys):
    command, name, changes = CASES[case]
    path = scene_file(tmp_path, name, changes)
    capsys.readouterr()
    assert main([command, str(path), "--json", "--out", str(tmp_path / "out")]) == 0
    out, err = capsys.readouterr()
    rec = json.loads(out)                         # exactly one JSON document on stdout
    assert rec["kind"] == case
    assert "wrote" in err


def test_a_stopped_solve_with_json_prints_its_record_and_exits_1(tmp_path, capsys):
    """--json of a solve that stops: its one record (with the stop) on stdout, the one
    line saying why on stderr, exit 1, and the folder kept."""
    path = scene_file(tmp_path, "thesis-pzt-single-2d", YEOH_STOPS)
    capsys.readouterr()
    assert main(["solve", str(path), "--json", "--out", str(tmp_path / "out")]) == EXIT_FAILED
    out, err = capsys.readouterr()
    rec = json.loads(out)
    assert rec["stop"]["requested"] == 5.0 and rec == json.loads((tmp_path / "out" / "result.json").read_text())
    failed = [line for line in err.splitlines() if line.startswith("taxel: failed: ")]
    assert len(failed) == 1 and "of 5 N" in failed[0]
