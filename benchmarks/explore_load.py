"""The explorer under load: ten well-behaved pages and two hostile clients on loopback.

Starts `taxel explore thesis-pzt-single-2d` on a free port (with its token), then in
one run, on one machine:

1. one page alone moves a control for `--seconds`, each move waited for;
2. `--tabs` pages at once, the same way (each its own connection and design);
3. `--tabs` pages at once (each its own connection and design, page i on control
   SLIDERS[i % 6]) do the same for `--seconds`, while `--hostile` clients attack, each in its
   own process (so it competes with the pages for the cores, not for this process):
   - hostile 0, a flood: control changes and figure requests sent without waiting and
     without reading the answers (the server paces it, then closes it as a page that
     does not read; it reconnects);
   - hostile 1, long values and oversized frames: a 1 MB value (timed to its refusal),
     a WebSocket frame header claiming 4 GB, a wslink chunk header claiming 4 GB (each
     of the two closes its connection; it reconnects).

A page speaks the page's protocol (taxel.explore.client, as trame's page does when a
slider moves: `trame.state.update` of the control's text, the slider's next step,
ArrowRight x4, ArrowLeft x4, ...: designs seen before come back, and the explorer answers
them from memory; with `--fresh` every move is a design never seen, so each is solved,
written to docs/explore_load_fresh.json), and a move's latency is from sending it to the
pushed answer newer than it (the page's answer count up, busy false).

CPU time separated from waiting: per phase, the explorer's CPU seconds (psutil: user +
system of its process and children) against the phase's wall seconds; per move, the
server's own answer time (the page's "solved in" / "from the store in" milliseconds)
and the explorer's CPU milliseconds per move (its CPU seconds over the moves answered)
beside the latency: the rest is waiting (the 20 ms debounce, the lanes' queues, the
transport, and the other processes on these cores).

Reports p50/p95/max of the pages' latencies in both phases and their ratio (goal:
p95 with ten pages and two hostile clients within 2x one page alone), the hostile
clients' counts and the refusal times, and writes docs/explore_load.json (the docs read it).
Bounded: `--seconds` per phase (at most 600), `--tabs` at most 16, every loop ends at
its phase's deadline; loopback only.

    .venv/bin/python benchmarks/explore_load.py [--seconds 30] [--tabs 10] [--hostile 2]
"""

from __future__ import annotations

import argparse
import json
import os
import re
import struct
import tempfile
import threading
import time
from pathlib import Path

import psutil

from taxel.explore.browser import ExplorerProcess
from taxel.explore.client import Client
from taxel.explore.controls import NUMBERS

SLIDERS = ["silicone_above", "gap", "taxel_width", "piezo_thickness", "force", "silicone_below"]
STEPS = [1, 2, 3, 4, 3, 2, 1, 0]                     # ArrowRight x4, ArrowLeft x4, ...
RESULT = Path(__file__).resolve().parents[1] / "docs" / "explore_load.json"   # the docs read it ({bench})
PHASES: list[tuple[int, int]] = []                   # (pages, hostile) of each phase, in order


class Page:
    """One well-behaved page: its state as pushed to it."""

    def __init__(self, url: str):
        self.c = Client.of(url, timeout=60)
        self.state = self.c.call("trame.state.get")["result"]["state"]

    def pump(self, until, limit: float) -> dict:
        """Read pushes until `until(state)`; TimeoutError after `limit` s."""
        end = time.monotonic() + limit
        while not until(self.state):
            if time.monotonic() > end:
                raise TimeoutError("no answer within the limit")
            msg = self.c.next()
            if msg and str(msg.get("id", "")).startswith("publish:trame.state.topic"):
                self.state.update(msg.get("result") or {})
        return self.state


def solve_ms(text: str) -> float | None:
    m = re.search(r"in (\d+) ms", text or "")
    return float(m.group(1)) / 1e3 if m else None


def page(url: str, seconds: float, control: str, rows: list, errors: list, start: float, fresh: int | None = None):
    n = next(x for x in NUMBERS if x.name == control)
    try:
        p = Page(url)
        p.pump(lambda s: s["answers"] >= 1 and not s["busy"], 300)
        base = float(p.state[f"t_{control}"])
        time.sleep(max(0.0, start - time.time()))
        end, k = time.monotonic() + seconds, 0
        while time.monotonic() < end:
            before = p.state["answers"]
            value = (f"{base + STEPS[k % len(STEPS)] * n.step:.4g}" if fresh is None else   # the slider's steps
                     f"{base * (1 + 1e-5 * (64 * k + fresh + 1)):.9g}")                     # a new design each move
            t0 = time.monotonic()
            p.c.send("trame.state.update", [{"key": f"t_{control}", "value": value}])
            try:
                st = p.pump(lambda s, b=before: s["answers"] > b and not s["busy"], 60)
                rows.append((time.monotonic() - t0, solve_ms(st["answer_time"]), st["answer_time"].startswith("solved")))
            except TimeoutError as exc:
                errors.append(str(exc))
            k += 1
        p.c.close()
    except Exception as exc:                         # a page that could not run: an error of the run
        errors.append(f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")


def flood(url: str, seconds: float, counts: dict):
    """Control changes and figure requests, never waiting and never reading."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        try:
            c = Client.of(url, timeout=10)
            section = "trigger__5"
            while time.monotonic() < end:
                for i in range(50):
                    c.send("trame.state.update", [{"key": "t_silicone_above", "value": f"{0.5 + i * 0.05:.2f}"}])
                c.send("trame.trigger", section, [], {})
                counts["sent"] += 51
        except Exception:                              # closed by the server (a page that does not read)
            counts["closed"] += 1
            time.sleep(0.2)


def attacker(url: str, seconds: float, counts: dict, refusals: list):
    """A 1 MB value (timed to its refusal), then a 4 GB frame header, then a 4 GB chunk header."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        try:
            p = Page(url)
            t0 = time.monotonic()
            p.c.send("trame.state.update", [{"key": "t_gap", "value": "1" * 1_000_000}])
            p.pump(lambda s: s["e_gap"], 30)
            refusals.append(time.monotonic() - t0)
            p.c.ws.sock.sendall(bytes([0x82, 0xFF]) + struct.pack(">Q", 4 << 30) + os.urandom(4) + b"x" * 64)
            counts["frames"] += 1
            p.c.close()
            c = Client.of(url, timeout=10)
            c.ws.send_binary(struct.pack("<III", 7, 0, 0xFFFFFFFF) + b"x")
            counts["chunks"] += 1
            c.close()
        except Exception:
            counts["errors"] += 1
        time.sleep(0.2)


def cpu(proc: psutil.Process) -> float:
    total = 0.0
    for p in [proc, *proc.children(recursive=True)]:
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.Error:
            pass
    return total


def hostile_process(kind: str, url: str, seconds: float, start: float, queue) -> None:
    """A hostile client in its own process (not competing with the pages for this one's GIL)."""
    counts = {"sent": 0, "closed": 0, "frames": 0, "chunks": 0, "errors": 0}
    refusals: list[float] = []
    time.sleep(max(0.0, start - time.time()))
    if kind == "flood":
        flood(url, seconds, counts)
    else:
        attacker(url, seconds, counts, refusals)
    queue.put((counts, refusals))


def phase(app, tabs: int, seconds: float, hostile: int, fresh: bool = False) -> dict:
    import multiprocessing
    rows, errors, refusals = [], [], []
    counts = {"sent": 0, "closed": 0, "frames": 0, "chunks": 0, "errors": 0}
    start = time.time() + 10                        # the pages' first answers, then all start together
    threads = [threading.Thread(target=page, args=(app.url, seconds, SLIDERS[i % len(SLIDERS)], rows, errors, start,
                                                   i + 16 * PHASES.index((tabs, hostile)) if fresh else None))
               for i in range(tabs)]
    ctx = multiprocessing.get_context("spawn")
    queue = ctx.Queue()
    procs = [ctx.Process(target=hostile_process, args=(kind, app.url, seconds, start, queue))
             for kind in ("flood", "attacker")[:hostile]]
    for p in procs:
        p.start()
    proc = psutil.Process(app.proc.pid)
    for t in threads:
        t.start()
    time.sleep(max(0.0, start - time.time()))
    c0, t0 = cpu(proc), time.monotonic()
    for t in threads:
        t.join()
    wall = time.monotonic() - t0
    for _ in procs:
        got, ref = queue.get(timeout=120)
        for k, v in got.items():
            counts[k] += v
        refusals += ref
    for p in procs:
        p.join(30)
    lat = [r[0] for r in rows]
    solve = [r[1] for r in rows if r[1] is not None]
    return {"tabs": tabs, "hostile": hostile, "moves": len(rows), "errors": len(errors),
            "error_kinds": sorted(set(errors))[:3], "p50_s": pct(lat, 50), "p95_s": pct(lat, 95),
            "max_s": max(lat, default=float("nan")), "server_answer_p50_s": pct(solve, 50),
            "server_answer_p95_s": pct(solve, 95), "wait_p50_s": pct([a - b for a, b, _ in rows if b is not None], 50),
            "solved_fraction": sum(r[2] for r in rows) / max(len(rows), 1),
            "wall_s": wall, "server_cpu_s": (used := cpu(proc) - c0),
            "server_cpu_per_move_ms": 1e3 * used / max(len(rows), 1), "hostile_counts": counts,
            "long_value_refusal_p50_s": pct(refusals, 50), "long_value_refusal_max_s": max(refusals, default=None)}


def pct(xs: list[float], p: float) -> float:
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(round(p / 100 * (len(xs) - 1))))] if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--tabs", type=int, default=10)
    ap.add_argument("--hostile", type=int, default=2)
    ap.add_argument("--fresh", action="store_true",
                    help="every move a design never seen (each one solved), not the slider's steps back and forth")
    args = ap.parse_args()
    if not (0 < args.seconds <= 600 and 1 <= args.tabs <= 16 and 0 <= args.hostile <= 2):
        ap.error("--seconds in (0, 600], --tabs in 1..16, --hostile in 0..2")
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as out, ExplorerProcess("thesis-pzt-single-2d", Path(out) / "out", 300.0) as app:
        PHASES[:] = [(1, 0), (args.tabs, 0), (args.tabs, args.hostile)]
        alone = phase(app, 1, args.seconds, 0, args.fresh)
        pages = phase(app, args.tabs, args.seconds, 0, args.fresh)
        many = phase(app, args.tabs, args.seconds, args.hostile, args.fresh)
        refused = sum("refused" in ln for ln in app.log)
        tracebacks = sum("Traceback" in ln for ln in app.log)
    res = {"date": time.strftime("%Y-%m-%d"), "cores": os.cpu_count(), "load_average_before": load0,
           "load_average_after": os.getloadavg()[0], "seconds": args.seconds, "fresh": args.fresh, "alone": alone, "pages": pages, "loaded": many,
           "p95_ratio": many["p95_s"] / alone["p95_s"], "p50_ratio": many["p50_s"] / alone["p50_s"],
           "p95_ratio_pages_only": pages["p95_s"] / alone["p95_s"],
           "refusal_lines": refused, "tracebacks": tracebacks}
    result = RESULT.with_name("explore_load_fresh.json") if args.fresh else RESULT
    result.write_text(json.dumps(res, indent=1))
    print(f"slider-to-answer latency of well-behaved pages, {args.seconds:g} s per phase, loopback, "
          f"{os.cpu_count()} cores, load average {load0:.1f} before")
    print(f"{'pages':>5} {'hostile':>7} {'moves':>6} {'p50':>8} {'p95':>8} {'max':>8} {'answer p50':>10} "
          f"{'wait p50':>9} {'server CPU':>11} {'CPU/move':>9} {'solved':>7} {'errors':>6}")
    for r in (alone, pages, many):
        print(f"{r['tabs']:>5} {r['hostile']:>7} {r['moves']:>6} {r['p50_s']:>6.3f} s {r['p95_s']:>6.3f} s "
              f"{r['max_s']:>6.3f} s {r['server_answer_p50_s']:>8.3f} s {r['wait_p50_s']:>7.3f} s "
              f"{r['server_cpu_s'] / r['wall_s']:>9.2f} c {r['server_cpu_per_move_ms']:>6.1f} ms {100 * r['solved_fraction']:>5.0f} % {r['errors']:>6}")
        for e in r["error_kinds"]:
            print(f"      error: {e}")
    h = many["hostile_counts"]
    print(f"hostile: flood {h['sent']} messages sent, closed {h['closed']} times; {h['frames']} 4 GB frame headers, "
          f"{h['chunks']} 4 GB chunk headers; 1 MB values refused in {many['long_value_refusal_p50_s']:.3f} s "
          f"(median), at most {many['long_value_refusal_max_s'] or float('nan'):.3f} s")
    print(f"p95 ratio, {args.tabs} pages and {args.hostile} hostile over 1 page alone: {res['p95_ratio']:.2f} "
          f"({'within' if res['p95_ratio'] <= 2 else 'beyond'} the 2x goal); median {res['p50_ratio']:.2f}x; "
          f"{args.tabs} pages without the hostile clients: p95 {res['p95_ratio_pages_only']:.2f}x; "
          f"{refused} refusal lines, {tracebacks} tracebacks in the explorer's log; wrote {result}")


if __name__ == "__main__":
    main()
