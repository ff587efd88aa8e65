"""Command-line helpers shared by the `taxel` subcommands."""

from __future__ import annotations

import argparse
import math
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


def number(low: float | None = None, high: float | None = None, *, integer: bool = False,
           low_open: bool = False, high_open: bool = False, unit: str = ""):
    """An argparse `type=`: a finite number (an integer with `integer`) in the range
    [low, high] (`low_open`/`high_open`: the end excluded; None: no end). Anything else is
    refused while the command line is parsed, in one line naming the option and the range:
    "argument --f-max: give a number > 0 (Hz), got '-5'"."""
    lo = "" if low is None else f"{'>' if low_open else '>='} {low:g}"
    hi = "" if high is None else f"{'<' if high_open else '<='} {high:g}"
    kind = "an integer" if integer else "a number"
    wanted = f"{kind} {lo}{' and ' if lo and hi else ''}{hi}".strip() + (f" ({unit})" if unit else "")

    def parse(text: str):
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"give {wanted}, got {text!r}") from None
        if not math.isfinite(value) or (low is not None and (value <= low if low_open else value < low)) \
                or (high is not None and (value >= high if high_open else value > high)):
            raise argparse.ArgumentTypeError(f"give {wanted}, got {text!r}")
        return value
    parse.__name__ = kind
    return parse


def show_progress(args, stream=None):
    """A line per step of long work (meshing, assembly, factorization, each press load step,
    each sweep round: the `taxel.*` loggers' INFO records) on stderr, when it is a terminal;
    none under --quiet or --json (stdout then holds one JSON record). Returns the handler
    (for the caller to remove) or None."""
    import logging
    import sys
    import time
    stream = stream or sys.stderr
    if getattr(args, "quiet", False) or getattr(args, "json", False) or not stream.isatty():
        return None
    t0 = time.perf_counter()

    class Elapsed(logging.Formatter):
        def format(self, record):
            return f"taxel: [{time.perf_counter() - t0:7.1f} s] {record.getMessage()}"
    handler = logging.StreamHandler(stream)
    handler.setFormatter(Elapsed())
    log = logging.getLogger("taxel")
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    return handler
