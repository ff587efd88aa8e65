"""The explorer under load: 10 concurrent headless Chromium tabs moving sliders on loopback.

Starts `taxel explore thesis-pzt-single-2d` on a free port (with its token), then:

1. one user: one tab moves the silicone-above slider (ArrowRight, ArrowLeft, ... with
   real key presses over the DevTools protocol) for `--seconds`, each move waited for;
2. ten users: `--tabs` Chromium processes (each with a fresh --user-data-dir), each
   on its own thread, do the same at the same time for `--seconds`.

Each page times its own moves: performance.now() at the slider's keydown, and again
when the page shows an answer newer than the key press with the server idle (a
MutationObserver on the page's hidden answer count, #answers). Tab i moves slider
SLIDERS[i % 6] (ArrowRight x4, ArrowLeft x4, ...).
Reports the slider-to-number latency percentiles (p50, p95, max) and the errors (a
move whose number never changed within 60 s, a page script or DevTools failure) of
both runs, and the ratio of the p95s (goal: ten users within 2x of one).

Note what "the number" is with several tabs: trame keeps ONE state per server, shared
by every connection, so every tab shows the newest design any tab asked for, and a
tab's move is answered by the first answer after it (which may hold other tabs' moves
too). A move that does not change the design (another tab undid it) gets no answer:
counted as a no-op, not timed.
Bounded: `--seconds` per run (default 60), `--tabs` (default 10, at most 16).

    .venv/bin/python benchmarks/explore_load.py [--seconds 60] [--tabs 10]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import threading
import time

from taxel.explore.browser import Browser, ExplorerProcess

SLIDERS = ["silicone_above", "gap", "taxel_width", "piezo_thickness", "force", "silicone_below"]
THUMB = "document.getElementById('slider_{0}').closest('.v-slider').querySelector('[role=slider]')"
# a move is answered when the page shows an answer newer than the key press with the server idle
# (the hidden #answers reads "COUNT:BUSY"); with several tabs on one shared design, a move another
# tab undid (the design did not change) gets no answer: counted as a no-op, not timed
PROBE = """(() => {
  window.__lat = []; window.__noop = 0; const thumb = %s; const a = document.getElementById('answers');
  const count = () => parseInt(a.textContent.split(':')[0]);
  thumb.addEventListener('keydown', () => { window.__t0 = performance.now(); window.__c0 = count(); }, true);
  new MutationObserver(() => { if (window.__t0 !== undefined && count() > window.__c0
                                  && a.textContent.endsWith(':false')) {
      window.__lat.push(performance.now() - window.__t0); window.__t0 = undefined; } })
    .observe(a, {childList: true, subtree: true, characterData: true});
  return true; })()"""
FIRST = "(document.getElementById('voltage') || {textContent: ''}).textContent.trim()"
KEYS = [("ArrowRight", "ArrowRight", 39)] * 4 + [("ArrowLeft", "ArrowLeft", 37)] * 4


def user(url: str, seconds: float, lat: list, errors: list, noops: list, ready: threading.Barrier | None,
         slider: str) -> None:
    """One tab: open the page, then move its slider until `seconds` are over."""
    thumb = THUMB.format(slider)
    try:
        with Browser() as b:
            b.goto(url)
            b.wait(FIRST, 300, "the first voltage")
            b.js(PROBE % thumb)
            if ready is not None:
                ready.wait(600)
            end, k = time.monotonic() + seconds, 0
            while time.monotonic() < end:
                try:
                    before = b.js("window.__lat.length")
                    b.js(thumb + ".focus()")
                    b.key(*KEYS[k % len(KEYS)])
                    try:
                        b.wait(f"window.__lat.length > {before}", 5, "an answer")
                        lat.append(b.js("window.__lat[window.__lat.length - 1]") / 1e3)
                    except TimeoutError:           # no answer in 5 s: a no-op if the server is idle, else wait on
                        if b.js("document.getElementById('answers').textContent.endsWith(':false')"):
                            noops.append(1)
                        else:
                            b.wait(f"window.__lat.length > {before}", 60, "the voltage after a slider move")
                            lat.append(b.js("window.__lat[window.__lat.length - 1]") / 1e3)
                except (TimeoutError, RuntimeError) as exc:
                    errors.append(str(exc).splitlines()[0])
                k += 1
    except Exception as exc:                       # a tab that could not start: an error of the run
        errors.append(f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")


def run(url: str, tabs: int, seconds: float) -> tuple[list[float], list[str], int]:
    lat: list[float] = []
    errors: list[str] = []
    noops: list[int] = []
    ready = threading.Barrier(tabs) if tabs > 1 else None
    threads = [threading.Thread(target=user, args=(url, seconds, lat, errors, noops, ready,
                                                   SLIDERS[i % len(SLIDERS)])) for i in range(tabs)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return lat, errors, len(noops)


def pct(xs: list[float], p: float) -> float:
    xs = sorted(xs)
    return xs[min(len(xs) - 1, int(round(p / 100 * (len(xs) - 1))))] if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--tabs", type=int, default=10)
    args = ap.parse_args()
    if not (0 < args.seconds <= 600 and 1 <= args.tabs <= 16):
        ap.error("--seconds in (0, 600] and --tabs in 1..16")
    rows = []
    with tempfile.TemporaryDirectory() as out, ExplorerProcess("thesis-pzt-single-2d", out, 300.0) as app:
        for tabs in (1, args.tabs):
            t0 = time.monotonic()
            lat, errors, noops = run(app.url, tabs, args.seconds)
            rows.append((tabs, lat, errors, noops, time.monotonic() - t0))
        refused = sum("refused" in ln for ln in app.log)
    print(f"slider-to-number latency in the browser, {args.seconds:g} s of moves per run, loopback")
    print(f"{'tabs':>5} {'moves':>6} {'p50':>8} {'p95':>8} {'max':>8} {'errors':>7} {'no-ops':>7}")
    for tabs, lat, errors, noops, _ in rows:
        print(f"{tabs:>5} {len(lat):>6} {pct(lat, 50):>6.3f} s {pct(lat, 95):>6.3f} s "
              f"{max(lat, default=float('nan')):>6.3f} s {len(errors):>7} {noops:>7}")
        for e in sorted(set(errors))[:3]:
            print(f"      error: {e}")
    one, many = pct(rows[0][1], 95), pct(rows[1][1], 95)
    print(f"p95 ratio, {args.tabs} tabs over 1: {many / one:.2f} ({'within' if many <= 2 * one else 'beyond'} "
          f"the 2x goal); median {statistics.median(rows[1][1]) / statistics.median(rows[0][1]):.2f}x; "
          f"refused connections: {refused}")


if __name__ == "__main__":
    main()
