"""Bad scene input: `taxel solve` exits with code 2 and one line naming the problem.

Each case is a small scene (TOML text, raw bytes, or a path that is not a
readable scene file) and the words the one-line message must contain (usually
the offending key).
"""

from __future__ import annotations

import json

import pytest

from taxel.cli import EXIT_INPUT, main

# A small, fast scene (one PZT taxel, coarse mesh) for cases that get as far as meshing.
FAST = '''
[model]
type = "plane_strain"

[mesh]
size = "1 mm"
piezo_size = "0.25 mm"
'''
ARRAY = FAST + "\n[array]\n"
AXISYM = ARRAY.replace('"plane_strain"', '"axisymmetric"')
PLATE = FAST + '''
[plate]
width = "20 mm"
layers = [{material = "PVDF", thickness = "52 um"}]
'''

MISSING = object()      # the scene path does not exist
DIRECTORY = object()    # the scene path is a directory


def case(id, scene, *words):
    marks = []
    return pytest.param(scene, words, id=id, marks=marks)


CASES = [
    # ---- unknown / misspelt keys
    case("unknown-top-level-key", 'colour = "red"\n' + ARRAY, "unknown key 'colour'"),
    case("unknown-nested-key-colz", ARRAY + "colz = 2\n", "unknown key 'array.colz'"),
    case("unknown-supports-key", ARRAY + '[supports]\nbottm = "bonded"\n', "supports.bottm"),
    case("model-type-typo", ARRAY.replace('"plane_strain"', '"plane_strian"'),
         "model.type", "plane_strian"),
    case("mesh-order-3", ARRAY.replace("[mesh]\n", "[mesh]\norder = 3\n"), "mesh.order", "3"),
    case("mesh-piezo-layers-0", ARRAY.replace("[mesh]\n", "[mesh]\npiezo_layers = 0\n"),
         "mesh.piezo_layers"),
    # ---- quantities and units
    case("negative-silicone-thickness", ARRAY + 'silicone_below = "-1 mm"\n',
         "array.silicone_below", "negative"),
    case("zero-taxel-width", ARRAY + 'taxel_width = "0 mm"\n', "array.taxel_width", "positive"),
    case("missing-unit-number", ARRAY + "taxel_width = 4\n", "array.taxel_width", "missing unit"),
    case("missing-unit-string", ARRAY + 'taxel_width = "4"\n', "array.taxel_width", "missing unit"),
    case("unit-mismatch-force-in-mm", ARRAY + '[load]\nforce = "1 mm"\n', "load.force", "unit mismatch"),
    case("unit-mismatch-force-in-kPa", ARRAY + '[load]\nforce = "10 kPa"\n', "load.force", "unit mismatch"),
    case("friction-without-contact", ARRAY + '[load]\nkind = "indenter"\nradius = "1 mm"\nfriction = "sticking"\n',
         "load.friction", "load.contact = true"),
    case("unreadable-quantity", ARRAY + 'taxel_width = "abc mm"\n', "array.taxel_width", "abc mm"),
    # ---- geometry
    case("overlapping-taxels", ARRAY + 'cols = 2\ngap = "-1 mm"\n', "array.gap", "overlap"),
    case("both-array-and-plate", PLATE + "\n[array]\n[load]\nkind = \"indenter\"\nradius = \"1 mm\"\n",
         "[array]", "[plate]"),
    case("neither-array-nor-plate", FAST + '[load]\nforce = "1 N"\n', "[array]", "[plate]"),
    case("axisymmetric-3x3", AXISYM + "rows = 3\ncols = 3\n[load]\ntaxel = [1, 1]\n",
         "axisymmetric", "rows = cols = 1"),
    case("plate-layers-empty", FAST + '[plate]\nwidth = "20 mm"\nlayers = []\n'
         '[load]\nkind = "pressure"\npressure = "1 kPa"\n', "plate.layers"),
    case("plate-rectangle-without-width", FAST + '[plate]\nlayers = [{material = "PVDF", '
         'thickness = "52 um"}]\n[load]\nkind = "pressure"\npressure = "1 kPa"\n', "plate.width"),
    # ---- materials
    case("unknown-piezo-material", ARRAY + 'piezo = "PZT-9"\n', "unknown material 'PZT-9'"),
    case("unknown-silicone-material", ARRAY + 'silicone = "Sorta-Clear"\n',
         "unknown material 'Sorta-Clear'"),
    case("user-material-without-rho", ARRAY + 'silicone = "soft"\n[materials.soft]\n'
         'kind = "solid"\nE = 3.0e4\nnu = 0.45\n', "materials.soft", "rho"),
    case("user-material-bad-kind", ARRAY + 'silicone = "soft"\n[materials.soft]\n'
         'kind = "gel"\nrho = 1000.0\n', "materials.soft", "kind"),
    case("user-material-wrong-unit", ARRAY + 'silicone = "soft"\n[materials.soft]\n'
         'kind = "solid"\nC10 = "27.5 kg"\nK = "55 MPa"\nrho = "1070 kg/m^3"\n', "materials.soft", "C10", "Pa"),
    case("user-material-wrong-unit-in-a-matrix", ARRAY + 'piezo = "film"\n[materials.film]\nkind = "piezo"\n'
         'rho = 1780\nd = [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0], ["23 pC/m", 0, 0, 0, 0, 0]]\n',
         "materials.film", "d:", "C/N"),
    case("axisymmetric-pvdf", AXISYM + 'piezo = "PVDF"\n',
         "PVDF", "transversely isotropic"),
    # ---- load
    case("load-taxel-outside-array", ARRAY + "rows = 2\ncols = 2\n[load]\ntaxel = [2, 0]\n",
         "load.taxel", "outside"),
    case("load-taxel-negative", ARRAY + "[load]\ntaxel = [-1, 0]\n", "load.taxel", "outside"),
    case("load-footprint-outside-sensor", ARRAY + '[load]\nkind = "indenter"\nradius = "1 mm"\n'
         'offset = ["20 mm", "0 mm"]\n', "load", "outside the sensor"),
    case("between-without-neighbour", ARRAY + 'cols = 2\n[load]\nkind = "between"\n', "load.neighbour"),
    case("neighbour-not-adjacent", ARRAY + 'cols = 3\n[load]\nkind = "between"\nneighbour = [0, 2]\n',
         "load.neighbour", "next to"),
    case("between-rows-in-2d", ARRAY + 'rows = 2\n[load]\nkind = "between"\nneighbour = [1, 0]\n',
         "load.neighbour", "row"),
    case("indenter-without-radius", ARRAY + '[load]\nkind = "indenter"\n', "load.radius"),
    case("pressure-without-pressure", PLATE + '[load]\nkind = "pressure"\n', "load.pressure"),
    case("pressure-without-pressure-array", ARRAY + '[load]\nkind = "pressure"\n', "load.pressure"),
    case("plate-with-taxel-load", PLATE, "load.kind", "taxel"),
    case("axisymmetric-offset-load",
         AXISYM + '[load]\nkind = "indenter"\nradius = "1 mm"\noffset = ["1 mm", "0 mm"]\n',
         "axisymmetric", "load.offset"),
    # ---- supports and electrodes
    case("bottom-and-edges-free", ARRAY + '[supports]\nbottom = "free"\nedges = "free"\n',
         "supports", "free"),
    case("unknown-electrode-name", ARRAY + '[electrodes]\ntaxel_9_9 = "open"\n',
         "electrodes.taxel_9_9", "no such electrode"),
    case("bad-electrode-state", ARRAY + '[electrodes]\ntaxel_0_0 = "maybe"\n',
         "electrodes.taxel_0_0", "maybe"),
    case("electrode-state-without-unit", ARRAY + '[electrodes]\ntaxel_0_0 = "10"\n',
         "electrodes.taxel_0_0"),
    case("electrode-state-number", ARRAY + "[electrodes]\ntaxel_0_0 = 5\n", "electrodes.taxel_0_0"),
    case("no-grounded-electrode", ARRAY + '[electrodes]\nground = "open"\n', "electrodes", "ground"),
    # ---- the file itself
    case("invalid-toml-syntax", '[array\ntaxel_width = "4 mm"\n', "not valid TOML"),
    case("nonexistent-scene-file", MISSING, "no scene file", "missing-scene.toml"),

    # ---- once bugs: a bare 0 skipped the positive check, NaN, wrong material kind, odd paths
    case("zero-taxel-width-bare-number", ARRAY + "taxel_width = 0\n", "array.taxel_width"),
    case("zero-indenter-radius-bare-number", ARRAY + '[load]\nkind = "indenter"\nradius = 0\n',
         "load.radius"),
    case("zero-piezo-thickness-bare-number", ARRAY + "piezo_thickness = 0\n", "array.piezo_thickness"),
    case("nan-force", ARRAY + '[load]\nforce = "nan N"\n', "load.force"),
    case("solid-as-piezo", ARRAY + 'piezo = "Ecoflex-00-30"\n', "array.piezo"),
    case("symmetry-typo", ARRAY.replace("[model]\n", '[model]\nsymmetry = "quater"\n'), "model.symmetry"),
    case("symmetry-quarter-in-2d", ARRAY.replace("[model]\n", '[model]\nsymmetry = "quarter"\n'),
         "model.symmetry", "3d"),
    case("symmetry-quarter-off-centre", ARRAY.replace('"plane_strain"', '"3d"').replace(
        "[model]\n", '[model]\nsymmetry = "quarter"\n') + "cols = 2\n", "model.symmetry", "not centred"),
    case("symmetry-half-asymmetric-electrodes", ARRAY.replace("[model]\n", '[model]\nsymmetry = "half"\n')
         + 'cols = 3\n[load]\ntaxel = [0, 1]\n[electrodes]\ntaxel_0_0 = "ground"\n', "model.symmetry",
         "electrodes"),
    case("tolerance-percent-over-100", ARRAY.replace("[model]\n", '[model]\ntolerance = "120 %"\n'),
         "model.tolerance", "below 1"),
    case("tolerance-as-length", ARRAY.replace("[model]\n", '[model]\ntolerance = "2 mm"\n'), "model.tolerance"),
    case("tolerance-negative-percent", ARRAY.replace("[model]\n", '[model]\ntolerance = "-2 %"\n'),
         "model.tolerance"),
    case("loss-factor-as-frequency", ARRAY + '[dynamics]\npiezo_loss = "1 Hz"\n', "dynamics.piezo_loss"),
    case("dielectric-loss-100-percent", ARRAY + '[dynamics]\ndielectric_loss = "100 %"\n',
         "dynamics.dielectric_loss"),
    case("plate-indenter-beyond-edge", PLATE + '[load]\nkind = "indenter"\nradius = "8 mm"\n'
         'offset = ["5 mm", "0 mm"]\n', "load.radius", "half-width"),
    case("plate-indenter-wider", PLATE + '[load]\nkind = "indenter"\nradius = "30 mm"\n', "load.radius"),
    case("yeoh-user-silicone-without-c10", ARRAY.replace("[model]\n", '[model]\nsilicone = "yeoh"\n')
         + 'silicone = "gel"\n[materials.gel]\nkind = "solid"\nE = 1e5\nnu = 0.45\nrho = 1000\n',
         "materials.gel", "C10", "fit-yeoh"),
    case("scene-path-is-a-directory", DIRECTORY, "scene-dir"),
    case("scene-file-not-utf8", b'[array]\ntaxel_width = "4 mm"\n# \xff\xfe\n', "bad-input.toml"),
]


@pytest.mark.parametrize("scene, words", CASES)
def test_bad_input_exits_2_with_one_line(tmp_path, capsys, scene, words):
    if scene is MISSING:
        path = tmp_path / "missing-scene.toml"
    elif scene is DIRECTORY:
        path = tmp_path / "scene-dir"
        path.mkdir()
    elif isinstance(scene, bytes):
        path = tmp_path / "bad-input.toml"
        path.write_bytes(scene)
    else:
        path = tmp_path / "bad-input.toml"
        path.write_text(scene)

    code = main(["solve", str(path)])
    out, err = capsys.readouterr()

    assert code == EXIT_INPUT == 2, f"exit code {code}; stderr: {err!r}"
    lines = err.splitlines()
    assert len(lines) == 1 and err.endswith("\n"), f"stderr is not one line: {err!r}"
    line = lines[0]
    assert line.startswith("taxel: error:"), line
    for w in words:
        assert w in line, f"{w!r} not in {line!r}"
    assert out == "", f"bad input printed results: {out!r}"


def test_bad_input_table_is_large_enough():
    assert len(CASES) >= 18


USER_SILICONE = ARRAY + '''silicone = "soft-gel"

[materials.soft-gel]
kind = "solid"
E = 60000.0
nu = 0.49
rho = 1050.0
'''


def test_user_material_as_silicone(tmp_path, capsys):
    path = tmp_path / "user.toml"
    path.write_text(USER_SILICONE)
    assert main(["solve", str(path), "--json"]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    user = json.loads(out)

    # the same scene with the library silicone: the user material must change the answer
    ref_path = tmp_path / "ref.toml"
    ref_path.write_text(ARRAY + 'silicone = "Ecoflex-00-30"\n')
    assert main(["solve", str(ref_path), "--json"]) == 0
    ref = json.loads(capsys.readouterr().out)

    v_user = user["electrodes"]["taxel_0_0"]["voltage_V"]
    v_ref = ref["electrodes"]["taxel_0_0"]["voltage_V"]
    assert v_user < 0 and v_ref < 0             # PZT pressed: negative open-circuit voltage
    assert abs(v_user - v_ref) > 1e-3 * abs(v_ref)
    assert user["applied_force_N"] == pytest.approx(1.0)
    # a silicone given as E and nu has its strain reported too (it decides linear vs Yeoh)
    assert user["max_silicone_strain"] > 0.01
    assert user["max_silicone_strain"] == pytest.approx(ref["max_silicone_strain"], rel=0.8)


def test_user_material_as_silicone_plain_output(tmp_path, capsys):
    path = tmp_path / "user.toml"
    path.write_text(USER_SILICONE)
    assert main(["solve", str(path)]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    assert "taxel_0_0" in out and "applied force" in out


SILICONE_IN_UNITS = {"kind": '"solid"', "C10": '"27.5 kPa"', "C20": '"0.4 kPa"', "C30": '"0 Pa"',
                     "K": '"55 MPa"', "rho": '"1070 kg/m^3"'}
SILICONE_IN_SI = {"kind": '"solid"', "C10": "27500.0", "C20": "400.0", "C30": "0.0", "K": "55e6", "rho": "1070.0"}


@pytest.mark.parametrize("silicone", ["linear", "yeoh"])
def test_a_user_silicone_in_unit_strings_solves_as_in_si_numbers(tmp_path, capsys, silicone):
    """[materials.NAME] takes unit strings as every other table of a scene does: the scene
    converts them (taxel.scene.material_in_si), so the same silicone in SI numbers gives the
    same solve, to the last digit; it differs from the library's Ecoflex."""
    answers = []
    for name, table in (("units", SILICONE_IN_UNITS), ("si", SILICONE_IN_SI)):
        path = tmp_path / f"{name}.toml"
        force = '[load]\nforce = "0.1 N"\n' if silicone == "yeoh" else ""
        path.write_text(FAST.replace('type = "plane_strain"', f'type = "plane_strain"\nsilicone = "{silicone}"')
                        + '\n[array]\nsilicone = "my-silicone"\n' + force + "\n[materials.my-silicone]\n"
                        + "".join(f"{k} = {v}\n" for k, v in table.items()))
        assert main(["solve", str(path), "--json"]) == 0
        out, err = capsys.readouterr()
        assert err == ""
        answers.append(json.loads(out)["electrodes"]["taxel_0_0"]["voltage_V"])
    assert answers[0] == answers[1] and answers[0] < 0
