"""`taxel measure ...`: capture, import, export, rebuild and simulate measurements.

    taxel measure capture RIG [--seconds S] --out DIR [--quiet]
    taxel measure import FILE --rig RIG --out DIR [--format raw|csv|tdms|lvm]
    taxel measure export DIR --csv FILE [--raw]
    taxel measure rebuild DIR
    taxel measure simulate RIG --scene SCENE --input step|impulse|chirp|presses
                           [--port URL | --pty | --to FILE] [--corrupt P] [--seconds S] [--truth DIR]
                           [--model reduced|lumped|fem]
    taxel measure analyze DIR [--scene SCENE] [--input KIND] [--resolution HZ]
    taxel measure localize DIR --presses FILE [--scene SCENE]
    taxel measure calibrate DIR --scene SCENE [--step DIR] [--travel DIR] [--resolution HZ] [--model lumped|reduced]

RIG is a rig TOML file or a built-in rig (thesis-bench). Bad input: one line, exit 2.
"""

from __future__ import annotations

import sys
from pathlib import Path

from taxel.cli.files import number


def register(sub) -> None:
    p = sub.add_parser("measure", help="measured data: capture from a serial port, import, export, simulate a rig")
    msub = p.add_subparsers(dest="measure_command", required=True)
    q = msub.add_parser("capture", help="capture a serial stream into a measurement folder")
    q.add_argument("rig", help="rig TOML file or built-in rig name")
    q.add_argument("--seconds", type=number(0, low_open=True, unit="s"), default=None,
                   help="stop after S seconds (default: Ctrl-C or port end)")
    q.add_argument("--out", required=True, metavar="DIR", help="a new measurement folder")
    q.add_argument("--url", default=None, help="override the rig's port (a device path or pyserial URL)")
    q.add_argument("--quiet", action="store_true", help="no live progress")
    q.set_defaults(run=_capture)
    q = msub.add_parser("import", help="a raw dump, CSV, TDMS or LVM file into a measurement folder")
    q.add_argument("file")
    q.add_argument("--rig", required=True)
    q.add_argument("--out", required=True, metavar="DIR")
    q.add_argument("--format", choices=["raw", "csv", "tdms", "lvm"], default=None, help="default: from the suffix")
    q.set_defaults(run=_import)
    q = msub.add_parser("export", help="a measurement folder to CSV (SI, or counts with --raw)")
    q.add_argument("folder")
    q.add_argument("--csv", required=True, metavar="FILE")
    q.add_argument("--raw", action="store_true", help="ADC counts instead of SI values")
    q.set_defaults(run=_export)
    q = msub.add_parser("rebuild", help="decode raw.bin again into measurement.h5 and summary.json")
    q.add_argument("folder")
    q.set_defaults(run=_rebuild)
    q = msub.add_parser("simulate", help="a virtual rig streaming the models' signals")
    q.add_argument("rig")
    q.add_argument("--scene", required=True, help="scene file or built-in (e.g. thesis-pzt-3x3-2d)")
    q.add_argument("--input", required=True, choices=["step", "impulse", "chirp", "presses"])
    where = q.add_mutually_exclusive_group(required=True)
    where.add_argument("--port", metavar="URL", help="serve on a loopback TCP port: socket://127.0.0.1:PORT")
    where.add_argument("--pty", action="store_true", help="serve on a new pseudo-terminal (its path is printed)")
    where.add_argument("--to", metavar="FILE", help="write the byte stream to a file")
    q.add_argument("--corrupt", type=number(0, 1, high_open=True), default=0.0, metavar="P", help="flip or drop each byte with probability P")
    q.add_argument("--seconds", type=number(0, low_open=True, unit="s"), default=10.0,
                   help="the record's length (refused if its arrays would not fit in memory)")
    q.add_argument("--seed", type=number(0, 2**63 - 1, integer=True), default=0)
    q.add_argument("--seq0", type=number(0, 2**16 - 1, integer=True), default=0, help="first seq (wrap-around tests)")
    q.add_argument("--t0-us", type=number(0, 2**32 - 1, integer=True), default=0, help="first t_us (wrap-around tests)")
    q.add_argument("--no-crosstalk", action="store_true", help="skip the FEM crosstalk solves")
    q.add_argument("--between", type=number(0, 1), default=0.0, metavar="P",
                   help="--input presses: the fraction of presses at random points (between taxels, over the edges)")
    q.add_argument("--model", choices=["reduced", "lumped", "fem"], default="reduced",
                   help="the taxel's charge: the scene's reduced model from the FEM (default; MIMO, crosstalk "
                   "included), the seed's lumped model with FEM crosstalk weights, or an FEM transient")
    q.add_argument("--linger", type=number(0, 3600, unit="s"), default=1.0, help="seconds the port stays open after the stream")
    q.add_argument("--delay", type=number(0, 3600, unit="s"), default=0.0, help="--pty: seconds before the stream starts (time to "
                   "start the capture: opening a port empties its input buffer)")
    q.add_argument("--truth", metavar="DIR", help="where truth.npz and truth.json go (default: beside --to, "
                   "else out/simulate-INPUT)")
    q.set_defaults(run=_simulate)
    q = msub.add_parser("analyze", help="step fit, linearity, repeatability or frequency response of a measurement")
    q.add_argument("folder")
    q.add_argument("--scene", default=None, help="the measured array's scene: C_p, R_eff and the lumped model's FRF")
    q.add_argument("--input", default=None, choices=["step", "impulse", "chirp", "presses"],
                   help="the kind of record (default: recognised from the force channel)")
    q.add_argument("--resolution", type=number(0, low_open=True, unit="Hz"), default=1.0, metavar="HZ", help="H1 frequency resolution (chirp)")
    q.set_defaults(run=_analyze)
    q = msub.add_parser("localize", help="which taxel was pressed: largest-taxel confusion matrix and correct rate")
    q.add_argument("folder")
    q.add_argument("--presses", required=True, metavar="FILE",
                   help="JSON with the known presses: a list of {t, position: [row, col], xy_mm: [x, y] (optional: "
                        "the point, from taxel_0_0's centre)}, or the simulator's truth.json")
    q.add_argument("--scene", default=None, help="the array's scene: adds the model-based position and force estimator")
    q.set_defaults(run=_localize)
    q = msub.add_parser("calibrate", help="fit the charge gain and the chain's time constant to a chirp's FRF")
    q.add_argument("folder", help="a chirp measurement folder")
    q.add_argument("--scene", required=True, help="the measured array's scene (file or built-in)")
    q.add_argument("--step", default=None, metavar="DIR", help="a step measurement of the same taxel (tau check)")
    q.add_argument("--travel", default=None, metavar="DIR", help="a chirp with the actuator's travel recorded: the "
                   "silicone's modulus scale and loss factor, and the piezo coefficient scale, into the overlay")
    q.add_argument("--resolution", type=number(0, low_open=True, unit="Hz"), default=1.0, metavar="HZ")
    q.add_argument("--model", choices=["lumped", "reduced"], default="lumped",
                   help="the taxel model the chain is fitted on: the seed's lumped model, or the scene's reduced "
                   "model from the FEM")
    q.set_defaults(run=_calibrate)


def _capture(args):
    from taxel import measure as tm
    from taxel.studies.bench.capture import check_out, open_port, print_progress
    rig = tm.load_rig(args.rig, args.url)
    check_out(Path(args.out))
    port = open_port(rig)
    print(f"capturing {rig.port.url} ({rig.port.protocol}, {rig.n} channels) into {args.out}; Ctrl-C stops",
          file=sys.stderr)
    live = not args.quiet and sys.stderr.isatty()     # live progress on a terminal only: a log gets the result line
    res = tm.capture(rig, args.out, seconds=args.seconds, progress=print_progress if live else None, port=port)
    if live:
        print(file=sys.stderr)
    *vanished, line = res.summary()
    for v in vanished:
        print(v, file=sys.stderr)
    print(line)
    return 1 if res.ended in ("port vanished", "disk full") else 0


def _import(args):
    from taxel import measure as tm
    rig = tm.load_rig(args.rig)
    m = tm.import_file(args.file, rig, args.out, args.format)
    print(f"{len(m)} frames of {rig.n} channels from {args.file} in {m.folder}")


def _export(args):
    from taxel import measure as tm
    print("\n".join(tm.export_csv(args.folder, args.csv, raw=args.raw).summary()))


def _rebuild(args):
    from taxel import measure as tm
    m = tm.rebuild(args.folder)
    s = m.stats
    print(f"{len(m)} frames rebuilt from raw.bin; {s['crc_failures']} CRC failures, {s['seq_gaps']} seq gaps, "
          f"{s['resyncs']} resyncs")


def _simulate(args):
    from taxel import measure as tm
    from taxel.studies.bench import wire as W
    rig = tm.load_rig(args.rig)
    tm.check_record_fits(rig, args.seconds, "--seconds ")
    url = None
    if args.port:
        host, _, port = args.port.removeprefix("socket://").removeprefix("tcp://").rpartition(":")
        if host not in ("127.0.0.1", "localhost") or not port.isdigit():
            raise ValueError(f"--port {args.port!r}: give a loopback URL such as socket://127.0.0.1:5000")
        url = int(port)
    truth_dir = Path(args.truth) if args.truth else (Path(args.to).with_suffix(".truth") if args.to
                                                     else Path("out") / f"simulate-{args.input}")
    sim = tm.simulate(rig, args.scene, args.input, args.seconds, args.corrupt, seed=args.seed, seq0=args.seq0,
                      t0_us=args.t0_us, crosstalk=not args.no_crosstalk, model=args.model, between=args.between)
    sim.to_folder(truth_dir, stream=False)
    print(f"{sim.summary()[0]}; truth in {truth_dir}", flush=True)
    wire = sim.wire
    if args.to:
        try:
            Path(args.to).parent.mkdir(parents=True, exist_ok=True)
            Path(args.to).write_bytes(wire.data)
        except OSError as exc:
            raise ValueError(f"--to {args.to}: cannot write it ({exc.strerror or exc})") from None
        print(f"wrote {args.to}")
        return 0
    player = W.Player.pty(wire, rig.sampling.rate, args.linger, delay=args.delay) if args.pty else \
        W.Player.tcp(wire, rig.sampling.rate, url, args.linger)
    print(f"serving on {player.url} at {rig.sampling.rate:g} frames/s; Ctrl-C stops", flush=True)
    try:
        while not player.done.wait(0.2):
            pass
    except KeyboardInterrupt:
        print("stopped by Ctrl-C", file=sys.stderr)
    finally:
        player.stop()
    print(f"sent {player.sent} bytes")
    return 0


def _analyze(args):
    from taxel import measure as tm
    a = tm.analyze(args.folder, args.scene, args.input, args.resolution)
    written = a.to_folder()
    print("\n".join(a.summary()))
    print("wrote " + ", ".join(str(p) for p in written))


def _localize(args):
    from taxel import measure as tm
    res = tm.localize(args.folder, args.presses, args.scene)
    path = res.to_folder(Path(args.folder))
    print("\n".join(res.summary()))
    print(f"wrote {path}")


def _calibrate(args):
    from taxel import measure as tm
    cal = tm.calibrate(args.folder, args.scene, args.step, args.travel, args.resolution, args.model)
    paths = cal.to_folder()
    print("\n".join(cal.summary()))
    print("wrote " + ", ".join(str(p) for p in paths))
