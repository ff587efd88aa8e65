"""What a tolerance study's points say: each output's distribution and percentiles,
the yield against the study's requirements, and which tolerance matters (Sobol').

Yield: the fraction of the sampled parts meeting every requirement, with its 95 %
Clopper-Pearson interval (scipy.stats.binomtest); a failed point counts as a reject.
Sobol' indices (first-order S1 and total ST, 95 % bootstrap intervals) by SALib
(Saltelli's scheme and estimators; not re-implemented here), evaluated on a
surrogate fitted to the study's points, because Saltelli's N (d + 2) evaluations
are too many FEM solves: a full quadratic polynomial in the standardised
deviations z = (x - nominal) / sigma, fitted by least squares (numpy.linalg.lstsq).
Its error is measured on held-out points (5-fold cross validation: rms of the
held-out residuals over the output's standard deviation) and reported beside the
indices, so that the reader can judge the indices (a surrogate that cannot
follow the output has a held-out error near 1).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from itertools import combinations_with_replacement
from pathlib import Path

import numpy as np

from taxel.analyses.results.outputs import units_of as output_units
from taxel.studies.requirements import parse_requirements
from taxel.studies.tolerance import Spread, meets

PERCENTILES = (5, 50, 95)


def quadratic_basis(z: np.ndarray) -> np.ndarray:
    """[1, z_i, z_i z_j (i <= j)] columns of standardised inputs z (n, d)."""
    cols = [np.ones(len(z))] + [z[:, i] for i in range(z.shape[1])]
    cols += [z[:, i] * z[:, j] for i, j in combinations_with_replacement(range(z.shape[1]), 2)]
    return np.column_stack(cols)


@dataclass
class Surrogate:
    """y(z) ~ quadratic_basis(z) @ coef, z = (x - nominal) / sigma."""

    nominal: np.ndarray
    sigma: np.ndarray
    coef: np.ndarray
    validation_error: float          # held-out rms / std of y (5-fold)

    def __call__(self, x: np.ndarray) -> np.ndarray:
        return quadratic_basis((np.atleast_2d(x) - self.nominal) / self.sigma) @ self.coef


def fit_surrogate(spreads: list[Spread], x: np.ndarray, y: np.ndarray, folds: int = 5) -> Surrogate:
    """The quadratic surrogate of y(x) and its 5-fold held-out error."""
    nominal = np.array([s.nominal for s in spreads])
    sigma = np.array([s.sigma for s in spreads])
    B = quadratic_basis((x - nominal) / sigma)
    if len(y) < B.shape[1] + folds:
        raise ValueError(f"{len(y)} points are too few for a quadratic surrogate in {len(spreads)} parameters "
                         f"(at least {B.shape[1] + folds}); raise samples")
    coef = np.linalg.lstsq(B, y, rcond=None)[0]
    idx = np.arange(len(y)) % folds
    res = np.empty_like(y)
    for k in range(folds):
        c = np.linalg.lstsq(B[idx != k], y[idx != k], rcond=None)[0]
        res[idx == k] = y[idx == k] - B[idx == k] @ c
    err = float(np.sqrt(np.mean(res ** 2)) / (np.std(y) or 1.0))
    return Surrogate(nominal, sigma, coef, err)


def sobol_indices(spreads: list[Spread], fun, n: int = 1024, seed: int = 0) -> dict:
    """S1, ST and their 95 % intervals by SALib (Saltelli sampling, n base samples) of fun(x (m, d)) -> (m,)."""
    from SALib.analyze import sobol as sobol_analyze
    from SALib.sample import sobol as sobol_sample
    problem = {"num_vars": len(spreads), "names": [s.name for s in spreads],
               "bounds": [s.salib()[0] for s in spreads], "dists": [s.salib()[1] for s in spreads]}
    X = sobol_sample.sample(problem, n, calc_second_order=False, seed=seed)
    Si = sobol_analyze.analyze(problem, np.asarray(fun(X), float), calc_second_order=False, conf_level=0.95,
                               seed=seed)
    return {s.name: {"S1": float(Si["S1"][j]), "S1_conf": float(Si["S1_conf"][j]), "ST": float(Si["ST"][j]),
                     "ST_conf": float(Si["ST_conf"][j])} for j, s in enumerate(spreads)}


def yield_of(ok: np.ndarray) -> dict:
    """{"yield", "low", "high"}: the fraction of True and its 95 % Clopper-Pearson interval."""
    from scipy.stats import binomtest
    k, n = int(np.sum(ok)), len(ok)
    ci = binomtest(k, n).proportion_ci(0.95)
    return {"yield": k / n, "low": float(ci.low), "high": float(ci.high), "parts": n}


@dataclass
class ToleranceResult:
    """A tolerance study's answer (see the module docstring)."""

    name: str
    spreads: list[Spread]
    x: np.ndarray                               # (n, d) sampled values (nominal units)
    values: dict[str, np.ndarray]               # output -> (n,) SI, NaN for a failed point
    requirements: dict[str, tuple[str, float]]  # output -> (op, bound)
    sobol: dict[str, dict] = field(default_factory=dict)           # output -> parameter -> indices
    surrogate_error: dict[str, float] = field(default_factory=dict)
    kind = "tolerance"
    error = None

    def yields(self) -> dict[str, dict]:
        """Per requirement and "all": yield and its interval."""
        oks = {k: meets(self.values[k], *req) for k, req in self.requirements.items()}
        out = {k: yield_of(v) for k, v in oks.items()}
        if oks:
            out["all"] = yield_of(np.logical_and.reduce(list(oks.values())))
        return out

    def distribution(self, output: str) -> dict:
        v = self.values[output]
        v = v[np.isfinite(v)]
        return {"mean": float(v.mean()), "std": float(v.std(ddof=1)) if len(v) > 1 else 0.0,
                **{f"p{p:02d}": float(np.percentile(v, p)) for p in PERCENTILES}, "n": int(len(v))}

    def most_important(self, output: str) -> str | None:
        s = self.sobol.get(output)
        return max(s, key=lambda k: s[k]["ST"]) if s else None

    def outputs(self) -> dict[str, float]:
        """yield (all requirements), and <output>_p05 / _p50 / _p95 per output."""
        out = {"yield": self.yields()["all"]["yield"]} if self.requirements else {}
        for k in self.values:
            d = self.distribution(k)
            out.update({f"{k}_p{p:02d}": d[f"p{p:02d}"] for p in PERCENTILES})
        return out

    def record(self) -> dict:
        return {"kind": self.kind, "study": self.name,
                "parameters": [{"name": s.name, "nominal": s.nominal, "unit": s.unit,
                                "distribution": s.distribution, "tolerance": s.half_width} for s in self.spreads],
                "x": self.x.tolist(), "values": {k: [None if not np.isfinite(a) else float(a) for a in v]
                                                 for k, v in self.values.items()},
                "requirements": {k: list(v) for k, v in self.requirements.items()},
                "distribution": {k: self.distribution(k) for k in self.values}, "yield": self.yields(),
                "sobol": self.sobol, "surrogate_error": self.surrogate_error, "outputs": self.outputs()}

    def summary(self) -> list[str]:
        lines = [f"{self.name}: {len(self.x)} parts, tolerances "
                 + ", ".join(f"{s.name} {s.distribution} +-{s.half_width:g} {s.unit}".rstrip() for s in self.spreads)]
        for k in self.values:
            d = self.distribution(k)
            lines.append(f"  {k}: mean {d['mean']:.4g}, 5-95 % {d['p05']:.4g} .. {d['p95']:.4g}")
            if k in self.sobol:
                ranked = sorted(self.sobol[k].items(), key=lambda kv: -kv[1]["ST"])
                lines.append("    Sobol' total: " + ", ".join(f"{n} {i['ST']:.2f}+-{i['ST_conf']:.2f}"
                                                            for n, i in ranked)
                             + f" (surrogate held-out error {100 * self.surrogate_error[k]:.1f} %)")
        for k, y in self.yields().items():
            req = self.requirements.get(k)
            what = f"{k} {req[0]} {req[1]:g}" if req else "all requirements"
            lines.append(f"  yield {what}: {100 * y['yield']:.1f} % ({100 * y['low']:.1f}-{100 * y['high']:.1f} %)")
        return lines

    def __str__(self) -> str:
        return "\n".join(self.summary())

    def to_folder(self, out) -> list[Path]:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        path = out / "tolerance.json"
        path.write_text(json.dumps(self.record(), indent=1))
        return [path]


def analyze(name: str, spreads: list[Spread], x: np.ndarray, values: dict[str, np.ndarray],
            requirements: dict[str, str], sobol_n: int = 1024, seed: int = 0) -> ToleranceResult:
    """Distributions, yield and (surrogate) Sobol' indices of sampled outputs."""
    reqs = {}
    for k, text in requirements.items():
        if k not in values:
            raise ValueError(f"requirements.{k}: not an output of the study ({', '.join(values)})")
    known = output_units("tolerance")
    units_of = {k: known.get(k) for k in values}       # None: an output of unknown unit
    for k, r in parse_requirements(requirements, units_of).items():
        reqs[k] = (r.op, r.bound)
    res = ToleranceResult(name, spreads, x, values, reqs)
    for k, v in values.items():
        good = np.isfinite(v)
        if good.sum() < 2 or np.std(v[good]) == 0:
            continue
        try:
            sur = fit_surrogate(spreads, x[good], v[good])
        except ValueError:
            continue
        res.surrogate_error[k] = sur.validation_error
        res.sobol[k] = sobol_indices(spreads, sur, sobol_n, seed)
    return res


MAGNITUDES = ("sensitivity", "charge_sensitivity")


def noise_outputs(scene_data: dict, outputs: dict, band=None) -> dict:
    """min_detectable_force (N), snr (dB at the scene's load force) and dynamic_range (dB)
    of a point from its static outputs, through the scene's own [readout] over `band` (Hz;
    None: its readout.band, default 1-300 Hz):
    the quasi-static noise budget (taxel.analyses.solves.noise.quasi_static_noise); {} without a
    pressed taxel's voltage and charge."""
    from taxel.analyses.solves.noise import design_noise
    from taxel.scene import parse
    m = design_noise(parse({**scene_data, "name": "point"}), outputs, band=band)
    return {k: v for k, v in m.items() if v is not None}


def from_study(study, store, noise_band=None) -> ToleranceResult:
    """The ToleranceResult of a tolerance study from its store (studies.store.Store): the
    named outputs of every point (sensitivity and charge_sensitivity as magnitudes, crosstalk,
    ...) and its noise outputs over `noise_band` (noise_outputs)."""
    from taxel.studies.store import point_key
    spreads = study.spreads()
    names = [p.name for p in study.spec.parameters]
    points = study.points()
    rows = {r["key"]: r for r in store.rows()}
    xs, outs = [], []
    for pt in points:
        xs.append([float(str(pt[n]).split()[0]) if isinstance(pt[n], str) else float(pt[n]) for n in names])
        row = rows.get(point_key(study.scene_data(pt)))
        outs.append(((row or {}).get("result") or {}).get("outputs") or {})
    for pt, o in zip(points, outs):
        o.update(noise_outputs(study.scene_data(pt), o, noise_band) if o else {})
    keys = sorted({k for o in outs for k in o if isinstance(o[k], (int, float))})
    values = {k: np.array([o.get(k, np.nan) if o.get(k) is not None else np.nan for o in outs], float)
              for k in keys}
    values = {k: v for k, v in values.items() if np.isfinite(v).any()}   # e.g. dynamic_range without clipping
    for k in MAGNITUDES:                     # the taxel's sign is its poling: the spec is on |S|
        if k in values:
            values[k] = np.abs(values[k])
    return analyze(study.spec.name, spreads, np.array(xs), values, study.spec.requirements, seed=study.spec.seed)
