"""Long work shows a sign of life: a line per step on a terminal's stderr (meshing, assembly,
each press load step, each sweep round), none under --quiet or --json, none into a pipe.

The command runs in a subprocess whose stderr is a pseudo-terminal (pty), as on a user's
terminal; stdout is a pipe, so the JSON record can be read back exactly.
"""

from __future__ import annotations

import json
import os
import pty
import subprocess
import sys

import pytest

# a fast press (plane strain, a cylinder, coarse mesh): seven load steps in about 1 s
PRESS = ('[model]\ntype = "plane_strain"\n[mesh]\nsize = "2 mm"\npiezo_size = "0.5 mm"\n[array]\n'
         '[load]\nkind = "probe"\nradius = "1 mm"\ncontact = true\nshape = "cylinder"\nforce = "0.2 N"\n')


def on_a_terminal(*argv: str) -> tuple[int, str, str]:
    """(exit code, stdout, stderr) of `taxel ARGV` with stderr on a pseudo-terminal."""
    master, slave = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "taxel.cli", *argv], stdout=subprocess.PIPE, stderr=slave,
                            env={**os.environ, "MKL_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"})
    os.close(slave)
    err = b""
    while True:
        try:
            chunk = os.read(master, 4096)
        except OSError:                  # the terminal's other end closed: the process ended
            break
        if not chunk:
            break
        err += chunk
    out = proc.stdout.read().decode()
    proc.wait()
    os.close(master)
    return proc.returncode, out, err.decode().replace("\r\n", "\n")


@pytest.fixture(scope="module")
def press(tmp_path_factory):
    path = tmp_path_factory.mktemp("progress") / "press.toml"
    path.write_text(PRESS)
    return str(path)


def test_a_press_shows_a_line_per_load_step_on_a_terminal(press):
    code, out, err = on_a_terminal("solve", press)
    assert code == 0
    lines = err.splitlines()
    steps = [ln for ln in lines if "press step" in ln]
    assert all(ln.startswith("taxel: [") for ln in lines), err
    assert any("meshing" in ln for ln in lines) and any("assembled" in ln for ln in lines)
    assert len(steps) >= 3 and steps[0].split("press step ")[1].startswith("1:")
    assert "indenter (cylinder)" in out and "press step" not in out     # the answer on stdout, unchanged


@pytest.mark.parametrize("flag", ["--quiet", "--json"])
def test_quiet_and_json_show_no_progress(press, flag):
    code, out, err = on_a_terminal("solve", press, flag)
    assert code == 0
    assert "press step" not in err and "taxel: [" not in err, err
    if flag == "--json":
        assert json.loads(out)["scene"] == "press"
