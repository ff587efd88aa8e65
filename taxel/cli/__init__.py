"""The `taxel` command.

    taxel solve SCENE [--json] [--vtu FILE] [--solver NAME] [--out DIR]
    taxel lumped SCENE [--json] [--out DIR]
    taxel work-precision SCENE... [--force N]... [--out DIR] [--store DIR]   (the work-precision chart)
    taxel mesh SCENE -o FILE          (.msh with physical groups, or .vtu/.xdmf via meshio)
    taxel study run STUDY [--out DIR] [--workers N] [--scheduler ADDR] [--retry-failed]
    taxel study status DIR | taxel study export DIR --csv FILE
    taxel optimize OPT [--out DIR] [--workers N]
    taxel report DIR... --out OUT [--pdf]
    taxel demo [--out DIR] [--small] [--full] [--presses-3d N] [--no-answer-3d]
    taxel examples
    taxel measure capture|import|export|rebuild|simulate ...   (taxel/cli/measure.py)
    taxel material | explore | schema | reduce | skin ...

SCENE is a TOML file or the name of a built-in example. Bad input exits with
code 2 and one line naming the problem and the fix. Each command group is a module
of this package (solve, study, material, measure, explore, schema, reduce), a thin
shell over taxel.api and taxel.measure; this module parses and turns errors into
one line and an exit code.
"""

from __future__ import annotations

import argparse
import errno
import logging
import os
import sqlite3
import sys

from taxel.cli import explore, material, measure, reduce, schema, skin, solve, study
from taxel.cli.files import EXIT_FAILED, EXIT_INPUT, InputError, show_progress

# Imported after the command line is parsed (main): the scene schema pulls in pydantic,
# which `taxel --help` and a bad argument never need.
SceneError = None


def _import_scene() -> None:
    global SceneError
    from taxel.scene import SceneError


def main(argv=None):
    ap = _Parser(prog="taxel", description="Piezoelectric tactile sensor design tool")
    sub = ap.add_subparsers(dest="command", required=True)
    solve.register(sub)              # solve, work-precision, lumped, mesh, examples (taxel/cli/solve.py)
    study.register(sub)              # study, optimize, report, demo (taxel/cli/study.py)
    material.register(sub)           # taxel material ... (taxel/cli/material.py)
    measure.register(sub)            # taxel measure ... (taxel/cli/measure.py)
    explore.register(sub)            # taxel explore (taxel/cli/explore.py)
    schema.register(sub)             # taxel schema ... (taxel/cli/schema.py)
    reduce.register(sub)             # taxel reduce ... (taxel/cli/reduce.py)
    skin.register(sub)               # taxel skin ... (taxel/cli/skin.py)
    try:
        args = ap.parse_args(argv)
    except InputError as exc:
        return _error(str(exc))
    _import_scene()
    # a line per step of long work on a terminal's stderr; not where a command shows its own
    # progress per point (study run's bar, work-precision's lines, the demo's)
    handler = None if args.command in ("study", "work-precision", "demo") else show_progress(args)
    try:
        code = args.run(args)
    except SceneError as exc:
        return _error(str(exc))
    except BrokenPipeError:              # `taxel ... | head`: the reader left; not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except sqlite3.DatabaseError as exc:
        if "full" in str(exc).lower():    # "database or disk is full": the disk, not the store
            print("taxel: failed: results.sqlite: no space left on the device; free space and run the same "
                  "command again (finished points are kept)", file=sys.stderr)
            return EXIT_FAILED
        return _error(f"{getattr(exc, 'path', 'results.sqlite')}: the results store is corrupt or not a "
                      f"database ({exc}); move it aside and rerun")
    except OSError as exc:
        if exc.errno == errno.ENOSPC:    # not bad input: the machine; what is finished is kept
            print(f"taxel: failed: {exc.filename or 'the output folder'}: no space left on the device; free space "
                  "and run the same command again (finished points and written files are kept)", file=sys.stderr)
            return EXIT_FAILED
        where = exc.filename or ""
        return _error(f"{where}: {exc.strerror or exc}; check the path and its permissions" if where
                      else f"{exc.strerror or exc}; check the paths and their permissions")
    except (ValueError, KeyError) as exc:
        return _error(str(exc.args[0]) if exc.args else type(exc).__name__)
    except RuntimeError as exc:          # includes fem.hyperelastic.NewtonError
        print(f"taxel: failed: {_first_line(exc)}", file=sys.stderr)
        return EXIT_FAILED
    except MemoryError:
        print("taxel: failed: out of memory; coarsen the mesh or model less (a 2D model)", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("taxel: interrupted; finished points are kept, run again to resume", file=sys.stderr)
        return 130
    except Exception as exc:             # a bug: one line (TAXEL_DEBUG=1 shows the traceback)
        if os.environ.get("TAXEL_DEBUG"):
            raise
        print(f"taxel: internal error: {type(exc).__name__}: {_first_line(exc)} (TAXEL_DEBUG=1 for the "
              "traceback; please report it)", file=sys.stderr)
        return EXIT_FAILED
    finally:
        if handler is not None:
            logging.getLogger("taxel").removeHandler(handler)
    return code or 0


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2 through main()."""

    def error(self, message):
        raise InputError(f"{message} (taxel {self.prog.partition(' ')[2] or ''} --help for usage)".replace("  ", " "))


def _first_line(exc) -> str:
    text = str(exc)
    return text.splitlines()[0] if text else type(exc).__name__


def _error(message: str) -> int:
    print(f"taxel: error: {message.splitlines()[0] if message else 'bad input'}", file=sys.stderr)
    return EXIT_INPUT


if __name__ == "__main__":
    sys.exit(main())
