"""Plain language on a page: what a reader sees holds no code identifier and no number
printed to more than 4 significant figures.

`problems(html)` reads the text a browser shows (no tags, scripts, styles, nor the
<pre>/<code> blocks that show a file or a command on purpose) and returns each
offence with a few words around it:

  - a code identifier (not a file path, an electrode's name nor a plural "(s)"): a
    snake_case name (`min_detectable_force`), a dotted module path
    (`optimize.probe_front`), an UPPER_CASE constant (`PRODUCT_ERROR`), a call
    (`headline_front(`) or a Python repr (`{'`, `[0.2, `);
  - a number of more than 4 significant figures (`0.7386685`, `1.8000000000000002e-08`);
    digits of a date, a time of day, a version or a file name are not numbers, and a
    whole number is a count (exact).
"""

from __future__ import annotations

import re
from html.parser import HTMLParser

SKIP = {"script", "style", "pre", "code", "head", "title"}
IDENTIFIER = re.compile(r"\b[a-z][a-z0-9]*(?:_[a-z0-9]+)+\b"            # snake_case
                        r"|\b[a-z][a-z0-9_]*\.[a-z][a-z0-9_]*\.[A-Za-z_][A-Za-z0-9_]*\b"   # a.b.c
                        r"|\b[A-Z][A-Z0-9]*(?:_[A-Z0-9]+)+\b"          # UPPER_CASE
                        r"|\b[a-z_][a-z0-9_]*\(\)?"                     # a call
                        r"|\{'|\['|\[\d+\.\d+, ")                       # a repr
NUMBER = re.compile(r"(?<![\w.:/-])[-+]?(\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)(?![\w:/])")
NOT_NUMBERS = re.compile(r"\d{4}-\d{2}-\d{2}|\d{1,2}:\d{2}(:\d{2})?|\bv?\d+\.\d+\.\d+\b|[\w-]+\.(?:csv|json|toml|png|html)"
                         r"|(?<![\w.])(?=[0-9]*[a-f])[0-9a-f]{7,40}\b(?![-+.]\d)")
WORDS = ("e.g", "i.e")                       # prose abbreviations the dotted-path rule must not catch
# not code: a file path a page points to (a benchmark script, a CSV), an electrode's name
# (taxel_1_1: the name the CLI, the files and the rig use), a plural "(s)"
NOT_CODE = re.compile(r"[\w./-]+\.(?:py|md|toml|json|csv|png|html|txt)\b|\btaxel_\d+_\d+\b|\w\(s\)")


class _Text(HTMLParser):
    def __init__(self):
        super().__init__()
        self.depth = 0
        self.parts: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag in SKIP:
            self.depth += 1

    def handle_endtag(self, tag):
        if tag in SKIP and self.depth:
            self.depth -= 1

    def handle_data(self, data):
        if not self.depth:
            self.parts.append(data)


def visible_text(html: str) -> str:
    p = _Text()
    p.feed(html)
    return " ".join(" ".join(p.parts).split())


def significant(number: str) -> int:
    """Significant figures of a printed number: "0.00473" 3, "738" 3, "1.250" 4, "1e-08" 1."""
    mantissa = re.split(r"[eE]", number.lstrip("+-"))[0]
    digits = mantissa.replace(".", "").lstrip("0")
    if "." not in mantissa:
        digits = digits.rstrip("0") or digits      # 1000: 1 significant figure, as printed
    return len(digits)


def problems(html: str) -> list[str]:
    """Each code identifier and each number of more than 4 significant figures the page shows."""
    text = visible_text(html)
    out = []
    for m in IDENTIFIER.finditer(NOT_CODE.sub(" ", text)):
        if m.group(0).rstrip("(") in WORDS or re.fullmatch(r"[a-z]\(", m.group(0)):
            continue
        out.append(f"code identifier {m.group(0)!r}")
    clean = NOT_NUMBERS.sub(" ", text)
    for m in NUMBER.finditer(clean):
        if re.fullmatch(r"[-+]?\d+", m.group(1)):
            continue                               # a whole number is a count (unknowns, points), exact
        if significant(m.group(1)) > 4:
            out.append(f"{significant(m.group(1))} significant figures {m.group(1)!r}: "
                       f"…{clean[max(0, m.start() - 30):m.end() + 30]}…")
    return out
