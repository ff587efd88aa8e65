"""Command-line helpers shared by the `taxel` subcommands."""

from __future__ import annotations

from pathlib import Path

EXIT_INPUT, EXIT_FAILED = 2, 1     # bad input (one line naming the problem and the fix); a run that failed


class InputError(ValueError):
    """Bad command-line input; one line with the fix."""


def writable_file(path: str, what: str, suffixes: tuple[str, ...] | None = None) -> Path:
    """A file path to write later: its folder must exist; refused now, before any work."""
    p = Path(path)
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise InputError(f"{what} {p}: unknown file type '{p.suffix}'; use one of {', '.join(suffixes)}")
    if not p.parent.is_dir():
        raise InputError(f"{what} {p}: the folder {p.parent} does not exist; create it first")
    if p.is_dir():
        raise InputError(f"{what} {p}: is a folder; give a file name")
    existed = p.exists()
    try:                                  # open it now: a read-only folder or file system fails here
        with open(p, "ab"):
            pass
    except OSError as exc:
        raise InputError(f"{what} {p}: cannot write it ({exc.strerror or exc}); choose a writable path") from None
    if not existed:
        p.unlink(missing_ok=True)
    return p
