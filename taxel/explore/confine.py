"""Where the explorer's processes write: its output folder, and nothing else.

gmsh starts its FLTK toolkit's preferences at every `gmsh.initialize` (its option
defaults set the GUI's tooltips), and FLTK then rewrites `$HOME/.fltk/fltk.org/
fltk.prefs` and, where the process may, `/etc/fltk/fltk.org/fltk.prefs`: files
outside the output folder, rewritten by every explorer process and 3D worker
(`readConfigFiles=False`, `-noenv` and `-nopopup` do not stop it). meshing.build
initializes gmsh without write access to them where the process is root; for any
user, the explorer gives its process, and the 3D workers it spawns (they inherit
the environment), a private home and temporary folder inside its output folder
(`.home`, `.tmp`): FLTK's, matplotlib's and the temporary figures' files land there.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


def confine(folder: Path) -> Path:
    """Create the output folder (OSError, one line, when it cannot be: before serving)
    and point HOME, TMPDIR and the caches of this process and its children into it."""
    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    home, tmp = folder / ".home", folder / ".tmp"
    for d in (home, tmp):
        d.mkdir(exist_ok=True)
    probe = tmp / ".writable"
    probe.write_text("")                     # OSError here too: the folder is not writable
    probe.unlink()
    os.environ.update({"HOME": str(home), "TMPDIR": str(tmp), "MPLCONFIGDIR": str(home / ".matplotlib"),
                       "XDG_CACHE_HOME": str(home / ".cache"), "XDG_CONFIG_HOME": str(home / ".config")})
    tempfile.tempdir = str(tmp)
    return folder
