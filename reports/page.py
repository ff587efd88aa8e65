"""What every report page shares: the Page record of a written page (its index
card), the jinja2 templates, and the provenance section. Used by the page
builders (reports/build.py, reports/validation.py)."""

from __future__ import annotations

import base64
import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

import shutil

from taxel.reports import tables
from taxel.scene import SceneError
from taxel.studies.store import code_version


class Headline(NamedTuple):
    """One headline number: what it is, its value in an engineering unit, and the
    model it comes from (model type, mesh, silicone law), shown beside it."""
    label: str
    value: str
    model: str
    href: str | None = None     # where the model's number is explained (reports.answer_numbers: a ladder row)


class Banner(NamedTuple):
    """One warning on top of a page: its kind ("range": a result outside its model's
    range; "disagreement": two models apart by more than their error estimates;
    "verification": a prediction that failed its check) and one sentence naming the
    number and the fix."""
    kind: str
    text: str

    @property
    def heading(self) -> str:
        return BANNER_HEADINGS[self.kind]


BANNER_HEADINGS = {"range": "Outside the model's range.", "disagreement": "Models disagree.",
                   "verification": "Failed verification."}


@dataclass
class Page:
    """A written page and what its index card shows."""
    path: Path
    kind: str
    title: str
    numbers: list[Headline] = field(default_factory=list)
    banners: list[Banner] = field(default_factory=list)
    thumb: bytes | None = None                       # PNG of the key figure


def templates():
    """The jinja2 environment of reports/templates (autoescaped XHTML)."""
    import jinja2
    return jinja2.Environment(loader=jinja2.PackageLoader("taxel.reports", "templates"),
                              autoescape=True, trim_blocks=True, lstrip_blocks=True)


def provenance(folder: Path, scene_data: dict | None) -> list[dict]:
    """The provenance blocks of a page: the folder, the code version, the date, the scene."""
    rows = [{"item": "folder", "value": str(folder.resolve())}, {"item": "code version", "value": code_version()},
            {"item": "report date", "value": time.strftime("%Y-%m-%d %H:%M:%S")}]
    blocks = [{"type": "table", "table": tables.table(rows, ["item", "value"])}]
    if scene_data:
        blocks.append({"type": "details", "summary": "scene", "text": json.dumps(scene_data, indent=1)})
    return blocks


class ReportError(SceneError):
    """A folder that cannot be reported; one line with the fix."""


def read_json(path: Path):
    """A JSON file of a result folder; a corrupt one is one line naming it."""
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ReportError(f"{path}: not valid JSON ({getattr(exc, 'msg', exc)}); rerun the command that "
                          "wrote it") from None


def figures(paths, captions=None) -> dict:
    """A block of embedded figures at their natural size, each with its caption
    (`captions`, else reports.captions.caption of its file name)."""
    from taxel.reports.captions import caption
    paths = list(paths)
    for p in paths:
        if not p.read_bytes():
            raise ReportError(f"{p}: an image to embed is empty; rerun the command that wrote it")
    caps = captions or [caption(p) for p in paths]
    return {"type": "figures", "images": [{"src": data_uri(p.read_bytes()), "caption": c} for p, c in zip(paths, caps)]}


def csv_link(src: Path, out: Path, folder: Path) -> str | None:
    """Copy a full-precision CSV beside the page; its relative link."""
    if not src.exists():
        return None
    name = f"{folder.name}-{src.name}"
    shutil.copyfile(src, out / name)
    return name


def data_uri(png: bytes) -> str:
    """An embedded image: a page opens with no other file."""
    return "data:image/png;base64," + base64.b64encode(png).decode()
