"""The docs' picture of the report: the first 1280x800 screen of the main job's index
(the answer block), in headless Chromium.

Run: make demo; python docs/report_screenshot.py [out/demo/report/index.html]
(writes docs/guide/report-index.png)
"""

import sys
from pathlib import Path

from taxel.explore.browser import Browser

index = Path(sys.argv[1] if len(sys.argv) > 1 else "out/demo/report/index.html").resolve()
out = Path(__file__).parent / "guide" / "report-index.png"
with Browser(1280, 800) as b:
    b.call("Emulation.setDeviceMetricsOverride", width=1280, height=800, deviceScaleFactor=1, mobile=False)
    b.goto(index.as_uri())
    b.wait("document.readyState === 'complete' && [...document.images].every(i => i.complete)")
    b.screenshot(out)
print(f"wrote {out}")
