"""Shared by the fault-injection tests: a small file system made for a test, and
a way to fill it."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest


@pytest.fixture
def small_disk(tmp_path):
    """A 4 MiB tmpfs made for the test (needs root or CAP_SYS_ADMIN: skipped otherwise)."""
    disk = tmp_path / "disk"
    disk.mkdir()
    try:
        r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=4m", "tmpfs", str(disk)], capture_output=True,
                           text=True)
        why = r.stderr.strip() or f"exit {r.returncode}" if r.returncode else None
    except OSError as exc:                   # no mount command
        why = str(exc)
    if why:
        pytest.skip(f"cannot mount a small tmpfs here ({why}); the disk-full test needs root or CAP_SYS_ADMIN")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "-l", str(disk)], capture_output=True)


def fill(disk: Path) -> Path:
    """Write a filler file until the file system is full; return it (delete it to free the space)."""
    filler = disk / "filler"
    block = b"\0" * 4096
    with open(filler, "wb", buffering=0) as fh:
        try:
            while True:
                fh.write(block)
        except OSError as exc:
            assert exc.errno == 28           # ENOSPC
    return filler
