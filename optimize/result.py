"""What an optimization returns: one type for an optimum and for a front.

    result = taxel.run_optimization("thesis-pzt-front", "out/front")
    result.kind                  # "optimum" or "front"
    result.optimum               # driver.Result (x, metrics, success, message, nfev, history) or None
    result.runs                  # the front's epsilon-constraint runs (FrontRun: bound, result)
    result.nondominated          # the front's nondominated (sensitivity V/N, crosstalk) points
    result.reference             # the reference design's evaluation ({"x": {...}, metrics}) or None
    result.reference_dominated   # True / False, None without a front or a reference
    result.summary(), result.record(), result.to_folder("out/front")
    OptimizationResult.from_folder("out/front")

`to_folder` writes result.json (the whole record, readable back) beside the files
the report reads: optimum.json and optimum-history.csv for an optimum, front.json
for a front; the plots are drawn by taxel.reports.optimization.
"""

from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from taxel.optimize.driver import Result, pareto_front, violation
from taxel.optimize.relax import of_record

RESULT_FILE = "result.json"
# a base scene naming a readout: its numbers beside the open circuit's (taxel.analyses.solves.at_readout)
AT_READOUT = ("readout_sensitivity", "readout_crosstalk", "min_detectable_force")


def _at_readout(m: dict) -> str:
    """"; at the readout 2.93 V/N, crosstalk 7.54 %, minimum detectable force 397 uN" or "", and
    "; coverage 100 %, localization error 310 um" where the run judged them (optimize.coverage)."""
    from taxel.units import engineering
    judged = ("" if m.get("coverage") is None else f"; coverage {100 * m['coverage']:.3g} %") + \
        ("" if m.get("localization_error") is None else
         f"; localization error {engineering(m['localization_error'], 'm', 3)}")
    if m.get("readout_sensitivity") is None:
        return judged
    return judged + (f"; at the readout {engineering(m['readout_sensitivity'], 'V/N', 3)}"
            + (f", crosstalk {100 * m['readout_crosstalk']:.3g} %" if m.get("readout_crosstalk") is not None else "")
            + (f", minimum detectable force {engineering(m['min_detectable_force'], 'N', 3)}"
               if m.get("min_detectable_force") is not None else ""))


@dataclass
class FrontRun:
    """One epsilon-constraint run of a front: maximize sensitivity s.t. crosstalk <= bound."""
    bound: float                  # the crosstalk bound (ratio)
    result: Result


@dataclass
class Constraint:
    """A constraint of the spec: metric op bound (SI)."""
    metric: str
    op: str                       # "<=" or ">="
    bound: float

    def as_driver(self) -> tuple[str, str, float]:
        return (self.metric, self.op, self.bound)


KINDS = ("optimum", "front")          # result.json's "kind" of an optimization folder


@dataclass
class OptimizationResult:
    """The optimum or the front of an optimization spec, with the reference design."""
    name: str
    names: list[str]                           # the design variables
    units: list[str]                           # their units (x is in these)
    sense: str                                 # "maximize" or "minimize"
    metric: str                                # the objective's metric
    constraints: list[Constraint] = field(default_factory=list)
    optimum: Result | None = None
    runs: list[FrontRun] = field(default_factory=list)
    reference: dict | None = None              # {"x": {name: value}, metric: value, ...}
    fem_solves: int = 0                        # distinct FEM solves in the run's store
    requirements: dict = field(default_factory=dict)   # the spec's [requirements] (optimize.requirements)
    prices: list = field(default_factory=list)          # each binding requirement's price, searched (optimize.relax)
    paths: dict = field(default_factory=dict)          # variable -> its scene path ("array.gap")

    @property
    def kind(self) -> str:
        return "front" if self.runs else "optimum"

    @property
    def success(self) -> bool:
        """The optimum met its constraints; a front has at least one successful run."""
        if self.optimum is not None:
            return bool(self.optimum.success)
        return any(r.result.success for r in self.runs)

    @property
    def front_rows(self) -> list[dict]:
        """One row per successful front run: its bound, sensitivity, crosstalk and design."""
        return [{"crosstalk_bound": r.bound, "sensitivity_V_per_N": r.result.metrics["sensitivity"],
                 "crosstalk": r.result.metrics["crosstalk"],
                 **{k: r.result.metrics[k] for k in (*AT_READOUT, "coverage", "localization_error")
                    if r.result.metrics.get(k) is not None},
                 **{f"{n} ({u})": float(v) for n, u, v in zip(self.names, self.units, r.result.x)}}
                for r in self.runs if r.result.success and r.result.metrics.get("sensitivity") is not None]

    @property
    def nondominated(self) -> list[tuple[float, float]]:
        """The front's nondominated (sensitivity V/N, crosstalk) points."""
        return pareto_front([(r["sensitivity_V_per_N"], r["crosstalk"]) for r in self.front_rows])

    @property
    def reference_dominated(self) -> bool | None:
        """Is the reference design dominated by a front point (by more than 0.1 % in both)?"""
        if not self.runs or not self.reference or self.reference.get("sensitivity") is None:
            return None
        s0, c0 = self.reference["sensitivity"], self.reference["crosstalk"]
        return any(s >= s0 * (1 + 1e-3) and c <= c0 * (1 - 1e-3) for s, c in self.nondominated)

    @property
    def evaluations(self) -> int:
        """Optimizer evaluations, over every run."""
        return self.optimum.nfev if self.optimum is not None else sum(r.result.nfev for r in self.runs)

    def feasible_evaluations(self) -> list[dict]:
        """The metrics of every evaluated design that meets the spec's constraints."""
        runs = [self.optimum] if self.optimum is not None else [r.result for r in self.runs]
        return [h["metrics"] for r in runs for h in r.history
                if h["metrics"].get("sensitivity") is not None
                and all(violation(h["metrics"], c.as_driver()) <= 1e-9 for c in self.constraints)]

    def optimum_record(self) -> dict:
        """optimum.json: the optimum's design, objective, metrics and status."""
        r = self.optimum
        return {"x": dict(zip(self.names, map(float, r.x))), "units": dict(zip(self.names, self.units)),
                "objective": r.fun, "metrics": r.metrics, "constraints": r.constraints, "evaluations": r.nfev,
                "success": r.success, "message": r.message}

    def record(self) -> dict:
        return {"kind": self.kind, "name": self.name, "variables": dict(zip(self.names, self.units)),
                "objective": {self.sense: self.metric},
                "constraints": [[c.metric, c.op, c.bound] for c in self.constraints],
                "optimum": None if self.optimum is None else {**self.optimum_record(),
                                                               "history": self.optimum.history},
                "front": [{"crosstalk_bound": r.bound, "run": _run_record(r.result)} for r in self.runs],
                "nondominated": [{"sensitivity_V_per_N": s, "crosstalk": c} for s, c in self.nondominated],
                "reference": self.reference, "reference_dominated": self.reference_dominated,
                "evaluations": self.evaluations, "fem_solves": self.fem_solves,
                "requirements": self.requirements, "prices": [r.record() for r in self.prices],
                "paths": self.paths}

    def summary(self) -> list[str]:
        """Lines for a person: the reference, the optimum or each front point, the cost."""
        lines = []
        if self.reference and self.reference.get("sensitivity") is not None:
            lines.append(f"reference design {self.reference['x']}: sensitivity {self.reference['sensitivity']:.4g} "
                         f"V/N, crosstalk {100 * self.reference['crosstalk']:.2f} % (open circuit)"
                         + _at_readout(self.reference))
        if self.optimum is not None:
            r = self.optimum
            lines.append(f"{'optimum' if r.success else 'best found (requirements violated)'}: "
                         + ", ".join(f"{n} = {v:.4g}" for n, v in zip(self.names, map(float, r.x)))
                         + f"; {r.nfev} evaluations; {r.message}")
            lines.append("metrics: " + ", ".join(f"{k} {v:.4g}" for k, v in r.metrics.items() if v is not None))
            return lines + self.verdict()
        for row in self.front_rows:
            lines.append(f"  crosstalk <= {100 * row['crosstalk_bound']:.2f} %: sensitivity "
                         f"{row['sensitivity_V_per_N']:.4g} V/N, crosstalk {100 * row['crosstalk']:.2f} %"
                         + _at_readout(row) + ", "
                         + ", ".join(f"{n} {row[f'{n} ({u})']:.3g} {u}" for n, u in zip(self.names, self.units)))
        if self.reference_dominated is not None:
            lines.append(f"the reference design is "
                         f"{'DOMINATED (not on the front)' if self.reference_dominated else 'on the front'}")
        dropped = [r for r in self.runs if not (r.result.success and r.result.metrics.get("sensitivity") is not None)]
        lines.append(f"front: {len(self.front_rows)} of {len(self.runs)} runs on the front"
                     + (f" ({len(dropped)} dropped: " + "; ".join(
                         f"crosstalk <= {100 * r.bound:.3g} %: {r.result.message}" for r in dropped) + ")"
                        if dropped else "")
                     + f", {self.evaluations} optimizer evaluations, {self.fem_solves} distinct FEM solves in the store")
        return lines + self.verdict()

    def verdict(self) -> list[str]:
        """The requirements against the run's designs (optimize.answer): which design they choose,
        which requirement binds; when none meets them all, which is missed, by how much, and the closest."""
        from taxel.optimize.answer import Answer
        return Answer.of(self).lines() + [f"  {r.text(self.names, self.units, self.metric)}" for r in self.prices]

    def to_folder(self, out: str | Path) -> list[Path]:
        """Write result.json and the report's files (optimum.json + optimum-history.csv,
        or front.json) into `out`; returns the paths written."""
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        files = [out / RESULT_FILE]
        files[0].write_text(json.dumps(self.record(), indent=1))
        if self.optimum is not None:
            files += [out / "optimum.json", out / "optimum-history.csv"]
            files[1].write_text(json.dumps(self.optimum_record(), indent=1))
            _write_history(self.optimum, self.names, files[2])
        if self.runs:
            files.append(out / "front.json")
            files[-1].write_text(json.dumps({"front": self.front_rows, "reference": self.reference}, indent=1))
        return files

    @classmethod
    def from_folder(cls, folder: str | Path) -> OptimizationResult:
        """The result written by `to_folder`."""
        rec = json.loads((Path(folder) / RESULT_FILE).read_text(encoding="utf-8"))
        (sense, metric), = rec["objective"].items()
        return cls(rec["name"], list(rec["variables"]), list(rec["variables"].values()), sense, metric,
                   [Constraint(*c) for c in rec["constraints"]],
                   None if rec["optimum"] is None else _run_of(rec["optimum"], list(rec["variables"])),
                   [FrontRun(r["crosstalk_bound"], _run_of(r["run"], list(rec["variables"]))) for r in rec["front"]],
                   rec["reference"], rec["fem_solves"], rec.get("requirements", {}),
                   of_record(rec.get("prices", [])), rec.get("paths", {}))


def _run_record(r: Result) -> dict:
    return {"x": [float(v) for v in r.x], "objective": r.fun, "metrics": r.metrics, "constraints": r.constraints,
            "evaluations": r.nfev, "success": r.success, "message": r.message, "history": r.history}


def _run_of(rec: dict, names: list[str]) -> Result:
    x = rec["x"]
    x = [x[n] for n in names] if isinstance(x, dict) else x
    return Result(np.asarray(x, float), rec["objective"], rec["metrics"], rec["constraints"], rec["evaluations"],
                  rec["success"], rec["message"], rec["history"])


def _write_history(result: Result, names: list[str], path: Path) -> None:
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        keys = sorted(result.history[0]["metrics"]) if result.history else []
        w.writerow(["evaluation", "phase", *names, *keys])
        for i, h in enumerate(result.history):
            w.writerow([i, h["phase"], *h["x"], *[h["metrics"][k] for k in keys]])
