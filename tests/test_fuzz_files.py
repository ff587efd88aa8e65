"""Property-based fuzzing (hypothesis) of the parsers of outside data: the measured-data
importers (CSV, TDMS, LabVIEW LVM) through `taxel measure import`, and the exported
reduced-model files (`taxel reduce -o FILE.npz`, read back by ReducedModel.load).
The rig and optimization files are fuzzed in test_fuzz_schemas.py.

Every input must end one of two ways: accepted, and then every number it holds is
finite (no silent NaN or inf: the measurement's values and times, the model's
matrices); or refused with one line ("taxel: error: ..." and exit 2 through the CLI;
a one-line ValueError through the API). Never a traceback, never "internal error".

Inputs are valid files mutated at random (lines deleted, duplicated or cut, cells
replaced by what a person or a broken logger writes: empty, text, nan, inf, huge,
decimal commas; bytes flipped or the file cut short) plus files built from scratch.
Examples a run: 120 CSV, 80 LVM, 60 TDMS, 60 model files (about 30 s on one core;
times TAXEL_FUZZ_SCALE); no deadline, so a slow machine never fails them.
"""

from __future__ import annotations

import contextlib
import io
import os
import tempfile
import warnings
import zipfile
from pathlib import Path

import numpy as np
import pytest
from measure_util import rig_dict, rig_toml, write_lvm

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, example, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from taxel.cli import main  # noqa: E402

SCALE = max(1, int(os.environ.get("TAXEL_FUZZ_SCALE", "1")))
SETTINGS = dict(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                                      HealthCheck.function_scoped_fixture],
                derandomize=False, database=None)
NAMES = [c["name"] for c in rig_dict()["channels"]]

# what a cell may hold: numbers as text, and what broken files hold instead
CELL = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), st.integers(-2 ** 70, 2 ** 70).map(str),
                 st.sampled_from(["", " ", "nan", "NaN", "inf", "-inf", "1e400", "1,5", "x", "--", "0x10", "1e-400",
                                  "\t", '"1"', "1 2", "\x00", "é"]),
                 st.text(max_size=6))


def _valid_table(n=6):
    t = np.arange(n) / 2000.0
    v = np.linspace(0.1, 0.9, n * len(NAMES)).reshape(n, len(NAMES))
    return t, v


def _mutate_lines(lines: list[str], ops, sep: str) -> list[str]:
    out = list(lines)
    for op, i, j, cell in ops:
        if not out:
            break
        i %= len(out)
        if op == "delete":
            del out[i]
        elif op == "duplicate":
            out.insert(i, out[i])
        elif op == "cut":
            out[i] = out[i][: j % (len(out[i]) + 1)]
        elif op == "cell":
            cells = out[i].split(sep)
            cells[j % len(cells)] = cell
            out[i] = sep.join(cells)
        elif op == "junk":
            out.insert(i, cell)
    return out


OPS = st.lists(st.tuples(st.sampled_from(["delete", "duplicate", "cut", "cell", "cell", "cell", "junk"]),
                         st.integers(0, 60), st.integers(0, 40), CELL), min_size=1, max_size=5)


def _import(tmp: Path, name: str, content: bytes | str) -> tuple[int, str]:
    """(exit code, stderr) of `taxel measure import` of `content`; checks the outcome's form."""
    (tmp / "rig.toml").write_text(rig_toml(rig_dict()))
    path = tmp / name
    (path.write_bytes if isinstance(content, bytes) else path.write_text)(content)
    err, out = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out), warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)      # an invalid cast or overflow: silent garbage
        code = main(["measure", "import", str(path), "--rig", str(tmp / "rig.toml"), "--out", str(tmp / "m")])
    err = err.getvalue()
    assert "Traceback" not in err and "internal error" not in err, err
    if code == 0:
        from taxel import measure as tm
        m = tm.read(tmp / "m")
        values = np.asarray(m.values, float)
        assert np.isfinite(values).all(), f"{name}: imported non-finite values silently"
        assert np.isfinite(np.asarray(m.t_us, float)).all(), f"{name}: imported non-finite times silently"
    else:
        lines = err.splitlines()
        assert code == 2 and len(lines) == 1 and lines[0].startswith("taxel: error:"), (code, err)
        assert not (tmp / "m").exists(), "a refused import left its folder behind"
    return code, err


def _csv_text(head: list[str], rows: list[list[str]]) -> str:
    return "\n".join(",".join(r) for r in [head, *rows]) + "\n"


@settings(max_examples=120 * SCALE, **SETTINGS)
@given(ops=OPS, seq=st.booleans())
def test_fuzzed_csv_imports_or_fails_in_one_line(ops, seq):
    t, v = _valid_table()
    head = (["seq"] if seq else []) + ["t_us", *NAMES]
    rows = [([str(i)] if seq else []) + [str(int(t[i] * 1e6)), *(f"{x:.6g}" for x in v[i])] for i in range(len(t))]
    lines = _mutate_lines(_csv_text(head, rows).splitlines(), ops, ",")
    with tempfile.TemporaryDirectory() as tmp:
        _import(Path(tmp), "data.csv", "\n".join(lines) + "\n")


@settings(max_examples=40 * SCALE, **SETTINGS)
@given(head=st.lists(st.sampled_from(["seq", "t_us", "t_s", "time", *NAMES, "extra", ""]), max_size=14),
       rows=st.lists(st.lists(CELL, max_size=14), max_size=5))
def test_csv_from_scratch_imports_or_fails_in_one_line(head, rows):
    with tempfile.TemporaryDirectory() as tmp:
        _import(Path(tmp), "data.csv", _csv_text(head, rows))


@settings(max_examples=80 * SCALE, **SETTINGS)
@given(ops=OPS, decimal=st.sampled_from([".", ","]), sep=st.sampled_from(["\t", ","]))
# found by this test on 2026-11-28: a segment header whose data rows are all cut (an internal error then)
@example(ops=[("duplicate", 0, 0, "0.0"), ("delete", 0, 0, "0.0"), ("cut", 51, 0, "0.0")], decimal=".", sep="\t")
def test_fuzzed_lvm_imports_or_fails_in_one_line(ops, decimal, sep):
    if decimal == "," and sep == ",":
        sep = "\t"
    t, v = _valid_table()
    with tempfile.TemporaryDirectory() as tmp:
        write_lvm(Path(tmp) / "valid.lvm", NAMES, t, v, decimal, sep)
        lines = _mutate_lines((Path(tmp) / "valid.lvm").read_text().splitlines(), ops, sep)
        _import(Path(tmp), "data.lvm", "\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def tdms_bytes(tmp_path_factory) -> bytes:
    from nptdms import ChannelObject, GroupObject, TdmsWriter
    t, v = _valid_table(8)
    path = tmp_path_factory.mktemp("tdms") / "valid.tdms"
    with TdmsWriter(path) as w:
        w.write_segment([GroupObject("bench"), ChannelObject("bench", "time", t),
                         *(ChannelObject("bench", n, v[:, j]) for j, n in enumerate(NAMES))])
    return path.read_bytes()


@settings(max_examples=60 * SCALE, **SETTINGS)
@given(flips=st.lists(st.tuples(st.integers(0, 10 ** 6), st.integers(0, 255)), max_size=6),
       cut=st.one_of(st.none(), st.integers(0, 10 ** 6)),
       nan_values=st.booleans())
def test_fuzzed_tdms_imports_or_fails_in_one_line(tdms_bytes, flips, cut, nan_values):
    data = bytearray(tdms_bytes)
    if nan_values:              # a channel's float64 samples overwritten with NaN (a bad logger)
        data[-8:] = np.array([np.nan]).tobytes()
    for pos, byte in flips:
        data[pos % len(data)] = byte
    if cut is not None:
        data = data[: cut % (len(data) + 1)]
    with tempfile.TemporaryDirectory() as tmp:
        _import(Path(tmp), "data.tdms", bytes(data))


# ----------------------------------------------------------------------------- exported model files
@pytest.fixture(scope="module")
def model_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("reduced") / "model.npz"
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["reduce", "thesis-pzt-single-2d", "-o", str(path)]) == 0
    return path


ARRAY_CHANGES = st.sampled_from(["nan", "inf", "shape", "drop", "text", "empty", "bool", "scale"])
META_CHANGES = st.sampled_from(["drop-key", "null", "text", "nan", "list", "truncate"])


def _load(path: Path):
    from taxel.analyses.solves.reduced import ReducedModel
    try:
        model = ReducedModel.load(path)
    except ValueError as exc:
        assert "\n" not in str(exc) and str(path) in str(exc), str(exc)
        return None
    ss = model.to_scipy() if hasattr(model, "to_scipy") else None
    for name in ("A", "B", "C", "D"):
        assert np.isfinite(getattr(model._ss, name)).all(), f"{name} holds non-finite values, accepted silently"
    return ss


@settings(max_examples=40 * SCALE, **SETTINGS)
@given(data=st.data())
def test_fuzzed_model_files_load_or_fail_in_one_line(model_file, data):
    import json
    with np.load(model_file, allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    meta = json.loads(str(arrays.pop("meta")))
    keys = sorted(arrays)
    for _ in range(data.draw(st.integers(1, 3))):
        if data.draw(st.booleans()):
            k, change = data.draw(st.sampled_from(keys)), data.draw(ARRAY_CHANGES)
            a = arrays.get(k)
            if a is None:
                continue
            if change == "nan" and a.dtype.kind == "f" and a.size:
                a = a.copy()
                a.flat[data.draw(st.integers(0, a.size - 1))] = np.nan
            elif change == "inf" and a.dtype.kind == "f" and a.size:
                a = a.copy()
                a.flat[0] = np.inf
            elif change == "shape":
                a = a.reshape(-1)[: max(a.size - 1, 0)]
            elif change == "drop":
                arrays.pop(k)
                continue
            elif change == "text":
                a = np.array("x")
            elif change == "empty":
                a = np.zeros((0, 0))
            elif change == "bool":
                a = a.astype(bool)
            elif change == "scale" and a.dtype.kind in "fc":
                with np.errstate(over="ignore"):
                    a = a * 1e300
            arrays[k] = a
        else:
            k, change = data.draw(st.sampled_from(sorted(meta))), data.draw(META_CHANGES)
            if change == "drop-key":
                meta.pop(k)
            elif change == "null":
                meta[k] = None
            elif change == "text":
                meta[k] = "x"
            elif change == "nan":
                meta[k] = float("nan")
            elif change == "list":
                meta[k] = [1, [2]]
    text = json.dumps(meta)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model.npz"
        np.savez_compressed(path, meta=np.array(text), **arrays)
        _load(path)


@settings(max_examples=20 * SCALE, **SETTINGS)
@given(flips=st.lists(st.tuples(st.integers(0, 10 ** 7), st.integers(0, 255)), min_size=1, max_size=4),
       cut=st.one_of(st.none(), st.integers(0, 10 ** 7)))
def test_damaged_model_files_fail_in_one_line(model_file, flips, cut):
    data = bytearray(model_file.read_bytes())
    for pos, byte in flips:
        data[pos % len(data)] = byte
    if cut is not None:
        data = data[: cut % (len(data) + 1)]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model.npz"
        path.write_bytes(bytes(data))
        _load(path)


def test_the_unmutated_files_are_accepted(model_file, tdms_bytes, tmp_path):
    """The fuzz starts from files that load: a mutation, not the base, is what is refused."""
    from taxel.analyses.solves.reduced import ReducedModel
    assert ReducedModel.load(model_file).to_scipy() is not None
    assert zipfile.is_zipfile(model_file)
    (tmp_path / "a").mkdir()
    assert _import(tmp_path / "a", "data.tdms", tdms_bytes)[0] == 0
    t, v = _valid_table()
    (tmp_path / "b").mkdir()
    write_lvm(tmp_path / "b" / "valid.lvm", NAMES, t, v)
    assert _import(tmp_path / "b", "data.lvm", (tmp_path / "b" / "valid.lvm").read_text())[0] == 0
