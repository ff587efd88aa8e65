"""The explorer over an optimization folder: the front, the current design on it,
and the current design sent back as an optimization's starting point.

An optimization folder (written by `OptimizationResult.to_folder`) holds the
front's designs (or the optimum) with their sensitivity (|V| of the pressed
taxel per newton, open circuit, V/N) and crosstalk (largest neighbour / pressed
voltage ratio). Nothing is solved here: the points are the stored result's. A
design variable of the optimization is matched to the explorer control of the
same name (silicone_above, gap, ...) or of the same scene path; its value is
converted to the control's display unit. Variables without a control are named
in `unmatched` and not loaded.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from taxel.analyses.results import result_kind
from taxel.explore.controls import NUMBERS, Number
from taxel.optimize.metrics import METRIC_TABLE, PLAIN
from taxel.optimize.result import KINDS, OptimizationResult
from taxel.units import quantity


def _control(name: str) -> Number | None:
    return next((n for n in NUMBERS if name in (n.name, n.path, n.path.rsplit(".", 1)[-1])), None)


@dataclass
class FrontDesign:
    """One design of the front: its label, metrics and the controls' values (display unit)."""

    label: str
    sensitivity: float          # V/N
    crosstalk: float            # ratio
    values: dict[str, float]    # control name -> value in the control's unit


@dataclass
class Front:
    """The stored front (or optimum) of an optimization folder, as the explorer shows it."""

    result: OptimizationResult
    designs: list[FrontDesign]
    unmatched: list[str] = field(default_factory=list)

    @classmethod
    def of(cls, folder: str | Path) -> Front | None:
        """The front of `folder`, or None when it is not an optimization folder."""
        if result_kind(folder) not in KINDS:
            return None
        r = OptimizationResult.from_folder(folder)
        runs = [(f"crosstalk <= {100 * run.bound:.2f} %", run.result) for run in r.runs]
        if r.optimum is not None:
            runs.append(("optimum", r.optimum))
        designs = []
        for label, res in runs:
            m = res.metrics
            if not res.success or m.get("sensitivity") is None or m.get("crosstalk") is None:
                continue
            values = {}
            for name, unit, x in zip(r.names, r.units, res.x):
                n = _control(name)
                if n is not None:
                    values[n.name] = round(float(quantity(f"{float(x)!r} {unit}" if unit else str(float(x)))
                                                 .to(n.unit).magnitude), 6)
            designs.append(FrontDesign(label, float(m["sensitivity"]), float(m["crosstalk"]), values))
        return cls(r, designs, [n for n in r.names if _control(n) is None])

    def rows(self) -> list[dict]:
        """The page's table of front designs."""
        units = {n.name: n.unit for n in NUMBERS}
        return [{"i": i, "label": d.label, "sensitivity": f"{d.sensitivity:.4g} V/N",
                 "crosstalk": f"{100 * d.crosstalk:.2f} %",
                 "design": ", ".join(f"{k} {v:g} {units[k]}" for k, v in d.values.items())}
                for i, d in enumerate(self.designs)]

    def image(self, current: tuple[float, float] | None) -> str:
        """Sensitivity against crosstalk: the front's designs, the reference design, and
        the current design (sensitivity V/N, crosstalk ratio) as a star; a PNG data URL."""
        from taxel.explore.session import png_data_url
        from taxel.reports.figures import pyplot
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(5, 3.2), constrained_layout=True)
        pts = sorted((d.crosstalk, d.sensitivity) for d in self.designs)
        ax.plot([100 * c for c, _ in pts], [s for _, s in pts], "o-", color="#2e86c1", label="front designs")
        ref = self.result.reference
        if ref and ref.get("sensitivity") is not None:
            ax.plot(100 * ref["crosstalk"], ref["sensitivity"], "s", color="grey", label="reference")
        if current is not None:
            ax.plot(100 * current[1], current[0], "*", ms=14, color="#c0392b", label="current design")
        ax.set_xlabel("crosstalk (%)")
        ax.set_ylabel("sensitivity (V/N)")
        ax.set_title(f"{self.result.name}: {self.result.kind}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        url = png_data_url(fig)
        plt.close(fig)
        return url

    def optimization_data(self, values: dict[str, float], base: str) -> dict:
        """An optimization spec (TOML data) with the current design as its start: the
        result's objective, requirements and front size; each matched variable at its
        control's scene path, bounded by the control's range (widened to hold the
        start), starting at `values` (control name -> display value); `base` the
        exported scene file of the current design."""
        r = self.result
        variables = {}
        for name in r.names:
            n = _control(name)
            if n is None or n.name not in values:
                continue
            v = float(values[n.name])
            variables[name] = {"path": n.path, "min": f"{min(n.low, v):g} {n.unit}",
                               "max": f"{max(n.high, v):g} {n.unit}", "start": f"{v:g} {n.unit}"}
        requirements = dict(r.requirements)       # the one table the search obeys (older folders: their constraints)
        for c in r.constraints:
            unit = METRIC_TABLE[c.metric].unit
            requirements.setdefault(c.metric, f"{c.op} {c.bound:.9g}" + ("" if unit in PLAIN else f" {unit}"))
        data = {"name": f"{r.name}-from-explorer", "base": base, "variables": variables,
                "objective": {r.sense: r.metric}, "requirements": requirements}
        if r.kind == "front":
            data["pareto"] = {"points": max(2, len(r.runs))}
        return data
