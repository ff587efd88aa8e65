"""Measured data from Python, flat: the bench's data in and out, and its analysis.

    import taxel.measure as tm

    rig = tm.load_rig("thesis-bench")
    sim = tm.simulate(rig, "thesis-pzt-3x3-2d", "presses", seconds=20)     # the simulated rig
    sim.to_folder("out/sim")                                                # stream.bin, truth.npz, ...
    m = tm.import_file("out/sim/stream.bin", rig, "out/m")                  # a measurement folder
    a = tm.analyze(m.folder, "thesis-pzt-3x3-2d")                           # linearity of each taxel
    a.to_folder()                                                           # analysis.json (+ CSV) in out/m
    tm.Analysis.read("out/m")                                               # and back

Every result is a dataclass with the same protocol as the analyses' results:
`record()` (JSON-ready), `summary()` (lines for a person), `to_folder(dir)` (its
files) and the class method `read(folder)` (the object again). The command line
(`taxel measure ...`) is a shell over these functions. Bad input raises
MeasurementError (or RigError, SceneError, ValueError) with one line naming the
file or key and the fix.

The bench's side is studies.bench (protocol, rig, folder, capture, importers,
export, simulate), the analysis of measured data studies.measured, the models'
predictions taxel.analyses (crosstalk, influence, localization, bench_model).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from taxel.scene import Scene
from taxel.studies.bench.capture import CaptureResult
from taxel.studies.bench.export import CsvExport
from taxel.studies.bench.folder import Measurement, MeasurementError
from taxel.studies.bench.rig import Rig, RigError
from taxel.studies.bench.simulated_run import Simulation
from taxel.studies.measured.analysis import Analysis
from taxel.studies.measured.calibrate import FolderCalibration
from taxel.studies.measured.localize import Localization, PressEvent
from taxel.studies.measured.pipeline import Validation

__all__ = ["load_rig", "capture", "import_file", "export_csv", "read", "rebuild", "simulate", "analyze", "calibrate",
           "localize", "validate", "Rig", "Measurement", "CaptureResult", "CsvExport", "Simulation", "Analysis",
           "FolderCalibration", "Localization", "PressEvent", "Validation", "MeasurementError", "RigError"]


def _scene(scene: Scene | str | Path | None) -> tuple[Scene | None, str | None]:
    """(the scene, its name as given) from a Scene, a scene file or a built-in name; its materials checked."""
    if scene is None:
        return None, None
    from taxel.analyses import check
    from taxel.scene import load
    sc = scene if isinstance(scene, Scene) else load(scene)
    check(sc)
    return sc, None if isinstance(scene, Scene) else str(scene)


def _rig(rig: Rig | str | Path) -> Rig:
    return rig if isinstance(rig, Rig) else load_rig(rig)


def load_rig(rig: str | Path, url: str | None = None) -> Rig:
    """A validated rig.

    Parameters
    ----------
    rig : str or path
        A rig TOML file or a built-in rig's name (``thesis-bench``, ``thesis-bench-travel``).
    url : str, optional
        Replaces the rig's port (a device path or a pyserial URL).

    Returns
    -------
    Rig
        The port, sampling, ADC, channels and conditioning, in SI.
    """
    from taxel.studies.bench.rig import load_rig as load, parse_rig
    r = load(rig)
    if url:
        r = parse_rig({**r.model_dump(), "port": {**r.port.model_dump(), "url": url}}, si_numbers=True)
    return r


def capture(rig: Rig | str | Path, out: str | Path, seconds: float | None = None, url: str | None = None,
            progress: Callable[[str], None] | None = None, stop=None, port=None) -> CaptureResult:
    """Capture the rig's serial stream into a new measurement folder.

    Parameters
    ----------
    rig : Rig, str or path
        The rig (or its file or built-in name).
    out : path
        A new (or empty) folder.
    seconds : float, optional
        Stop after this long (default: Ctrl-C, `stop` set, or the port's end).
    url : str, optional
        Replaces the rig's port.
    progress : callable, optional
        Called with a one-line progress report about once a second.
    stop : threading.Event, optional
        Ends the capture when set.
    port : serial port, optional
        The rig's port, already open (studies.bench.capture.open_port); default: opened here.

    Returns
    -------
    CaptureResult
        The folder, how the capture ended, and its summary.json (`stats`); `.measurement()` reads it.
    """
    from taxel.studies.bench.capture import capture as run, check_out, open_port
    if seconds is not None and not seconds > 0:
        raise ValueError(f"--seconds must be positive, got {seconds}")
    r = load_rig(rig, url) if not isinstance(rig, Rig) else rig
    check_out(Path(out))
    return run(r, Path(out), seconds=seconds, stop=stop, progress=progress, port=port or open_port(r))


def import_file(path: str | Path, rig: Rig | str | Path, out: str | Path, format: str | None = None) -> Measurement:
    """A raw dump, CSV, TDMS or LVM file into a new measurement folder.

    Parameters
    ----------
    path : path
        The file.
    rig : Rig, str or path
        The rig it was taken with.
    out : path
        A new (or empty) folder.
    format : {"raw", "csv", "tdms", "lvm"}, optional
        Default: from the file's suffix.

    Returns
    -------
    Measurement
        The folder, read.
    """
    from taxel.studies.bench.importers import import_file as run
    return run(path, _rig(rig), out, format)


def export_csv(folder: str | Path, csv: str | Path, raw: bool = False) -> CsvExport:
    """A measurement folder as CSV: ``seq,t_us,<channels>``, one row per frame, in SI (or ADC counts).

    Returns
    -------
    CsvExport
        The file and its row count; `import_file` reads it back.
    """
    from taxel.studies.bench.export import export
    return export(folder, csv, raw)


def read(folder: str | Path) -> Measurement:
    """A measurement folder (frames, rig, summary.json)."""
    from taxel.studies.bench.folder import read as run
    return run(folder)


def rebuild(folder: str | Path) -> Measurement:
    """Decode a folder's raw.bin again into measurement.h5 and summary.json (after kill -9)."""
    from taxel.studies.bench.folder import rebuild as run
    return run(folder)


# The simulator holds the whole record in memory: per frame and channel about this many bytes
# (float64 truth arrays, the noisy volts, the counts and the encoded stream, with numpy's
# temporaries). Measured as the growth of peak RSS (/usr/bin/time -f %M) from --seconds 20 to
# 160 on thesis-bench (10 channels, 2000 frames/s): 52 B (chirp, --model lumped) and 12 B
# (presses, reduced); rounded up.
BYTES_PER_FRAME_CHANNEL = 64.0
MEMORY_SHARE = 0.5           # of this machine's physical memory: the most a simulated record may take


def check_record_fits(rig: Rig, seconds: float, option: str = "seconds = ") -> None:
    """A simulated record's length refused (ValueError naming `option`), before any work,
    where its arrays would not fit in MEMORY_SHARE of this machine's memory."""
    from taxel.meshing.cost import machine_memory
    frames = seconds * rig.sampling.rate
    need, have = frames * rig.n * BYTES_PER_FRAME_CHANNEL, MEMORY_SHARE * machine_memory()
    if need > have:
        raise ValueError(f"{option}{seconds:g}: {frames:.3g} frames of {rig.n} channels would need about "
                         f"{need / 1e9:.3g} GB, more than {have / 1e9:.3g} GB (half this machine's memory); "
                         f"give at most {option}{have / (rig.sampling.rate * rig.n * BYTES_PER_FRAME_CHANNEL):.0f}")


def simulate(rig: Rig | str | Path, scene: Scene | str | Path, input: str = "step", seconds: float = 10.0,
             corrupt: float = 0.0, **settings) -> Simulation:
    """The simulated rig: the models' signals through the rig's chain, as the bytes it would send.

    Parameters
    ----------
    rig : Rig, str or path
        The rig simulated.
    scene : Scene, str or path
        The sensor (a taxel-array scene).
    input : {"step", "impulse", "chirp", "presses"}
        The force applied.
    seconds : float
        The record's length.
    corrupt : float
        The probability that each byte is flipped or dropped.
    **settings
        Any other field of studies.bench.signals.Settings (seed, crosstalk, model, between, ...).

    Returns
    -------
    Simulation
        The truth and the byte stream; `to_folder(dir)` writes stream.bin, truth.npz, truth.json, rig.json.
    """
    from taxel.studies.bench.signals import INPUTS, Settings
    from taxel.studies.bench.simulated_run import run
    if input not in INPUTS:
        raise ValueError(f"input {input!r}: choose one of {', '.join(INPUTS)}")
    rig = _rig(rig)
    check_record_fits(rig, seconds)
    sc, _ = _scene(scene)
    return run(rig, sc, Settings(input=input, seconds=seconds, **settings), corrupt)


def analyze(folder: str | Path, scene: Scene | str | Path | None = None, input: str | None = None,
            resolution: float = 1.0, fem: bool = True) -> Analysis:
    """Step fit, linearity, repeatability or frequency response of a measurement folder.

    Parameters
    ----------
    folder : path
        A measurement folder.
    scene : Scene, str or path, optional
        The measured array's scene: C_p, R_eff and the models' FRFs.
    input : {"step", "impulse", "chirp", "presses"}, optional
        The kind of record (default: recognised from the force channel).
    resolution : float
        H1's frequency resolution, Hz (chirp).
    fem : bool
        With a scene, the FEM's frequency sweep beside the lumped model (chirp).

    Returns
    -------
    Analysis
        Not yet written: `to_folder()` writes analysis.json (+ CSV) into the measurement folder.
    """
    from taxel.studies.measured.analysis import analyze_folder
    sc, name = _scene(scene)
    return analyze_folder(folder, sc, name, input, resolution, fem=fem)


def calibrate(folder: str | Path, scene: str | Path, step: str | Path | None = None,
              travel: str | Path | None = None, resolution: float = 1.0, model: str = "lumped") -> FolderCalibration:
    """Fit the charge gain and the chain's time constant to a chirp's FRF (and with `travel` the silicone).

    Parameters
    ----------
    folder : path
        A chirp's measurement folder.
    scene : str or path
        The measured array's scene file or built-in name (the calibrated scene overlays it).
    step : path, optional
        A step of the same taxel: its tau beside the calibrated one.
    travel : path, optional
        A chirp with the actuator's travel recorded: the silicone's modulus scale and loss factor.
    resolution : float
        H1's frequency resolution, Hz.
    model : {"lumped", "reduced"}
        The taxel model the chain is fitted on: the seed's lumped model, or the scene's
        reduced model from the FEM (its pressed path).

    Returns
    -------
    FolderCalibration
        Not yet written: `to_folder()` writes calibration.json and calibrated-scene.toml.
    """
    from taxel.studies.measured.calibrate import calibrate_folder
    if isinstance(scene, Scene):
        raise ValueError("calibrate: give the scene's file or built-in name (the calibrated scene overlays its TOML)")
    sc, name = _scene(scene)
    return calibrate_folder(folder, sc, name, step, travel, resolution, model)


def localize(folder: str | Path, presses: str | Path, scene: Scene | str | Path | None = None) -> Localization:
    """Which taxel was pressed (largest taxel), and with a scene where and how hard (all taxels).

    Parameters
    ----------
    folder : path
        A measurement folder of presses.
    presses : path
        JSON of the known presses: a list of {t, position: [row, col], xy_mm (optional)}, or the
        simulator's truth.json.
    scene : Scene, str or path, optional
        The array's scene: adds the model-based position and force estimator.

    Returns
    -------
    Localization
        Not yet written: `to_folder(dir)` writes localization.json.
    """
    from taxel.studies.bench.folder import read_rig
    from taxel.studies.measured.analysis import check_scene
    from taxel.studies.measured.localize import localize_folder
    sc, name = _scene(scene)
    if sc is not None:
        check_scene(sc, read_rig(folder), name or "scene")
    return localize_folder(folder, presses, sc)


def validate(root: str | Path, scene: str = "thesis-pzt-3x3-2d", rig: str = "thesis-bench",
             progress: Callable[[str], None] | None = print) -> Validation:
    """The validation loop on the simulated rig (studies.measured.pipeline): simulate, capture over a
    pseudo-terminal, analyze, calibrate, localize, one folder per record under `root`.

    Parameters
    ----------
    root : path
        Where the records and validation.json go.
    scene, rig : str
        The simulated sensor's scene and the rig (files or built-in names).
    progress : callable, optional
        Called with a line per record.

    Returns
    -------
    Validation
        validation.json (already written into `root`): measured, the simulator's truth, the thesis's figures.
    """
    from taxel.studies.measured.pipeline import run
    run(Path(root), scene, rig, progress=progress or (lambda line: None))
    return Validation.read(root)
