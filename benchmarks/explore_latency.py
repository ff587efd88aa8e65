"""Slider-to-number latency of `taxel explore`, measured in the browser.

Starts `taxel explore thesis-pzt-single-2d` on a free port, opens it in headless
Chromium (DevTools protocol) and moves the silicone-above slider with real key
presses. The page itself times each move: performance.now() at the key's
keydown on the slider, and again when the voltage's text node changes (a
MutationObserver). Side by side, one run: the 2D (plane strain) and the
axisymmetric model, each for new designs (a solve) and for designs seen before
(read from the study store, the slider moved back). Target: median <= 0.3 s.

    .venv/bin/python benchmarks/explore_latency.py [--moves 8] [--screenshot docs/guide/explorer.png]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile

from taxel.explore.browser import Browser, ExplorerProcess

THUMB = "document.getElementById('slider_silicone_above').closest('.v-slider').querySelector('[role=slider]')"
PROBE = """(() => {
  window.__lat = []; const thumb = %s; const v = document.getElementById('voltage');
  thumb.addEventListener('keydown', () => { window.__t0 = performance.now(); }, true);
  new MutationObserver(() => { if (window.__t0 !== undefined) {
      window.__lat.push(performance.now() - window.__t0); window.__t0 = undefined; } })
    .observe(v, {childList: true, subtree: true, characterData: true});
  return true; })()""" % THUMB


def moves(b: Browser, key: str, code: str, keycode: int, n: int) -> list[float]:
    """n slider moves, each waited for until the number changed; latencies in s."""
    out = []
    for _ in range(n):
        before = b.js("window.__lat.length")
        b.js(THUMB + ".focus()")
        b.key(key, code, keycode)
        b.wait(f"window.__lat.length > {before}", 60, "the voltage after a slider move")
        out.append(b.js("window.__lat[window.__lat.length - 1]") / 1e3)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--moves", type=int, default=8)
    ap.add_argument("--screenshot", default=None, help="save a screenshot of the page (PNG)")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as out, ExplorerProcess("thesis-pzt-single-2d", out) as app, Browser() as b:
        b.goto(app.url)
        b.wait("(document.getElementById('voltage') || {textContent: ''}).textContent.trim()", 180, "the first voltage")
        b.js(PROBE)
        for model in ("2D", "axisymmetric"):
            if model != "2D":
                b.js(f"window.trame.state.set('model', '{model}')")
                b.wait(f"document.getElementById('answer_model').textContent.includes('{model}')", 60, model)
            fresh = moves(b, "ArrowRight", "ArrowRight", 39, args.moves)       # new thicknesses: solved
            back = moves(b, "ArrowLeft", "ArrowLeft", 37, args.moves)          # the same ones back: stored
            rows.append((model, fresh, back))
        if args.screenshot:
            b.js("document.getElementById('section').click()")
            b.wait("(() => { const t = document.getElementById('figure_title').textContent;"
                   " return !t.includes('working') && t; })()", 180, "the section")
            b.wait("document.getElementById('figure').naturalWidth > 0", 30, "the section image")
            print(f"screenshot {b.screenshot(args.screenshot)}")
    print(f"slider-to-number latency in the browser (median of {args.moves} moves; target <= 0.300 s)")
    print(f"{'model':<14} {'new design (solve)':>20} {'seen before (store)':>20} {'ratio':>7}")
    for model, fresh, back in rows:
        f, s = statistics.median(fresh), statistics.median(back)
        print(f"{model:<14} {f:>18.3f} s {s:>18.3f} s {f / s:>7.1f}")
    worst = max(statistics.median(r[1]) for r in rows)
    print(f"worst median {worst:.3f} s: {'meets' if worst <= 0.3 else 'misses'} the 0.3 s target")


if __name__ == "__main__":
    main()
