"""The validation page of a measurement-validation folder (studies.measured.pipeline):
model against measurement on the (simulated) bench.

Sections: the summary table beside the thesis's figures; the step traces with
their first-order fits; the measured FRF (H1, the amplitude-spectrum ratio) with
its coherence against the lumped model before and after calibration; linearity
and repeatability; the largest-taxel confusion matrix and the model-based
position estimates; the calibration table with its 95 % intervals.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from taxel.reports.page import Page, provenance, templates
from taxel.reports.figures import pyplot as _plt
from taxel.reports.scene_sections import data_uri
from taxel.reports.tables import table


def _png_bytes(fig) -> bytes:
    import io
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    _plt().close(fig)
    return buf.getvalue()


def _figure(png: bytes, caption: str) -> dict:
    """A page block with one embedded figure and its caption."""
    return {"type": "figures", "images": [{"src": data_uri(png), "caption": caption}]}


def _noise(folder: Path) -> str:
    """The one noise figure of the localization: per sample, and per reading (the mean
    of the samples within 2 ms: studies.measured.readings.reading_noise)."""
    amap = folder / _loc_dir(folder) / "accuracy-map.json"
    if not amap.exists():
        return "1 mV rms per sample"
    per_reading = json.loads(amap.read_text())["noise_V"]
    n = round((1e-3 / per_reading) ** 2)
    return f"1 mV rms per sample, {1e3 * per_reading:.2g} mV per reading (the mean of {n} samples)"


def _step_figure(folder: Path):
    from taxel.studies.measured import events, peaks as analyze
    from taxel.studies.bench.folder import read
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 3.6))
    for d in sorted(folder.glob("step-*")):
        m = read(d)
        rec = events.record(m)
        a = json.loads((d / "analysis.json").read_text())
        for s in a["step"]:
            k = rec.names.index(s["taxel"])
            fit = analyze.StepFit(**{**s, "tau_ci95_s": tuple(s["tau_ci95_s"])})
            model = analyze.step_model(rec, fit, m.rig.chains()[s["taxel"]])
            ax.plot(rec.t, rec.volts[:, k], lw=0.5, alpha=0.6, label=f"{d.name} {s['taxel']} measured")
            ax.plot(rec.t, model, lw=1.2, label=f"fit tau = {s['tau_s']:.3g} s")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("output (V)")
    ax.legend(fontsize=7)
    ax.set_title("Step responses and first-order fits")
    fig.tight_layout()
    return fig


def _frf_figure(folder: Path):
    from taxel.studies.measured import frf as FR
    plt = _plt()
    a = json.loads((folder / "chirp" / "analysis.json").read_text())["frf"]
    cal = json.loads((folder / "chirp" / "calibration.json").read_text())
    f = np.array(a["freqs_Hz"])
    fig, (ax, axc) = plt.subplots(2, 1, figsize=(7, 5), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax.semilogy(f, a["H1_abs_V_per_N"], label="H1 (Welch)")
    ax.semilogy(f, a["ratio_V_per_N"], lw=0.7, label="amplitude-spectrum ratio")
    if "lumped" in a["models"]:
        ax.semilogy(f, a["models"]["lumped"]["abs_V_per_N"], "--", label="lumped model")
        from taxel.analyses import lumped_model
        from taxel.scene import load
        from taxel.studies.measured.calibrate import scaled_chain
        from taxel.studies.bench.folder import read_rig
        chain = read_rig(folder / "chirp").chains()[a["taxel"]].readout()
        r, _ = scaled_chain(chain, cal["tau_scale"])
        scene = json.loads((folder / "validation.json").read_text())["scene"]
        Hc = cal["gain"] * np.abs(FR.lumped_frf(lumped_model(load(scene)), r, f))
        ax.semilogy(f, Hc, ":", lw=1.5, label="lumped, calibrated")
    if "fem" in a["models"]:
        fem = np.array([np.nan if x is None else x for x in a["models"]["fem"]["abs_V_per_N"]], float)
        ax.semilogy(f, fem, "-.", label="FEM (2D)")
    ax.set_ylabel("|V/F| (V/N)")
    top = float(np.max(np.array(a["H1_abs_V_per_N"])[np.array(a["coherence"]) > 0.9]))
    ax.set_ylim(top / 30, top * 10)
    ax.set_xlim(0, f.max() / 10)
    ax.legend(fontsize=7)
    ax.set_title(f"Frequency response of {a['taxel']}")
    axc.plot(f, a["coherence"])
    axc.axhline(0.9, color="k", lw=0.5)
    axc.set_ylabel("coherence")
    axc.set_xlabel("frequency (Hz)")
    fig.tight_layout()
    return fig


def _linearity_figure(folder: Path):
    plt = _plt()
    a = json.loads((folder / "presses" / "analysis.json").read_text())
    r = json.loads((folder / "impulse" / "analysis.json").read_text())["repeatability"]
    fig, (ax, ay) = plt.subplots(1, 2, figsize=(11, 3.8), layout="constrained")
    for x in a["linearity"]:
        ax.plot(x["forces_N"], np.abs(x["peaks_V"]), "o", ms=3,
                label=f"{x['taxel'].removeprefix('taxel_')} R={abs(x['r']):.5f}")
    ax.set_xlabel("force peak (N)")
    ax.set_ylabel("|voltage peak| (V)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    ax.set_title("Linearity")
    for x in r:
        ay.plot(np.arange(1, x["n"] + 1), x["peaks_V"], "o-", label=f"{x['taxel']}: {x['by_spread_pct']:.2f} % / "
                f"{x['by_range_pct']:.2f} %")
    ay.set_xlabel("impulse (count)")
    ay.set_ylabel("|voltage peak| (V)")
    ay.legend(fontsize=7, loc="lower right")
    ay.set_title("Repeatability (spread / range)")
    return fig


def _localization_figure(folder: Path):
    plt = _plt()
    loc = json.loads((folder / _loc_dir(folder) / "localization.json").read_text())
    fig, (ax, ay) = plt.subplots(1, 2, figsize=(11, 4.8), layout="constrained")
    C = np.array(loc["confusion"])
    ax.imshow(C, cmap="Blues")
    for i in range(len(C)):
        for j in range(len(C)):
            if C[i, j]:
                ax.text(j, i, str(C[i, j]), ha="center", va="center", fontsize=7)
    ax.set_xticks(range(len(C)), [t.removeprefix("taxel_") for t in loc["taxels"]], fontsize=7)
    ax.set_yticks(range(len(C)), [t.removeprefix("taxel_") for t in loc["taxels"]], fontsize=7)
    ax.set_xlabel("estimated (largest taxel)")
    ax.set_ylabel("pressed")
    ax.set_title(f"Confusion matrix: {100 * loc['correct_rate']:.1f} % correct")
    mb = loc.get("model_based")
    amap_path = folder / _loc_dir(folder) / "accuracy-map.json"
    if amap_path.exists():
        amap = json.loads(amap_path.read_text())
        x, y = np.array(amap["x_mm"]), np.array(amap["y_mm"])
        im = ay.pcolormesh(x, y, np.array(amap["position_error_mm"], float), shading="nearest", cmap="viridis")
        fig.colorbar(im, ax=ay, label="predicted position error (mm)")
    if mb:
        for cls, marker, colour in (("on", "s", "w"), ("between", "o", "orange"), ("beyond the edge", "^", "cyan")):
            r = mb if cls == "on" else mb.get(cls.split()[0] if cls == "between" else "edge", {})
            if not r.get("presses"):
                continue
            e, t = np.array(r["per_press"]["estimate_mm"]), np.array(r["per_press"]["truth_mm"])
            ay.plot(t[:, 0], t[:, 1], marker, color=colour, ms=7, mfc="none",
                    label=f"pressed ({cls}{' taxels' if cls != 'beyond the edge' else ''})")
            ay.plot(e[:, 0], e[:, 1], "r.", ms=4, label="model-based estimate" if cls == "on" else None)
            for a, b in zip(t, e):
                ay.plot([a[0], b[0]], [a[1], b[1]], "r-", lw=0.5)
        ay.set_aspect("equal")
        ay.invert_yaxis()
        ay.set_xlabel("x (mm)")
        ay.set_ylabel("y (mm)")
        ay.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
        btw = mb.get("between", {}).get("position_error_mm", {}).get("median")
        on = mb["position_error_mm"].get("median", mb["position_error_mm"]["rms"])
        ay.set_title(f"Position error, median: {on:.2g} mm on taxels"
                     + (f", {btw:.2g} mm between" if btw is not None else ""), fontsize=9)
    return fig


def _loc_dir(folder: Path) -> str:
    return "presses-between" if (folder / "presses-between" / "localization.json").exists() else "presses"


def localization_rows(folder: Path) -> list[dict]:
    """Position and force errors of both estimators, on and between taxels."""
    loc = json.loads((folder / _loc_dir(folder) / "localization.json").read_text())
    rows = []
    mb = loc.get("model_based", {})
    for method, by_class in (("largest taxel", loc.get("largest_taxel", {})),
                             ("model-based", {"on": mb, "between": mb.get("between", {}), "edge": mb.get("edge", {})})):
        for cls in ("on", "between", "edge"):
            r = by_class.get(cls, {})
            if r.get("presses"):
                where = {"on": "on taxels", "between": "between taxels", "edge": "beyond the outer taxels"}[cls]
                rows.append({"method": method, "presses": where, "n": r["presses"],
                             "position error rms (mm)": r["position_error_mm"]["rms"],
                             "position error median (mm)": r["position_error_mm"]["median"],
                             "position error max (mm)": r["position_error_mm"]["max"],
                             "force error rms (%)": r["force_error_pct"]["rms"]})
    return rows


def _all_presses(v: dict) -> int:
    lt = v["measured"]["localization"].get("largest_taxel", {})
    return sum(r.get("presses", 0) for r in lt.values()) or v["measured"]["localization"]["presses"]


def summary_rows(v: dict, noise: str = "1 mV rms per sample") -> list[dict]:
    """The summary table: each figure measured here beside the thesis's."""
    m, th = v["measured"], v["thesis"]
    R = [abs(x) for x in m["linearity_R"].values()]
    loc = m["localization"]
    return [
        {"figure": "time constant, taxel 1 (s)", "thesis": th["tau_s"][0],
         "simulated rig": f"{m['tau'][0]['tau_s']:.4g}, 95 % {m['tau'][0]['ci95_s'][0]:.3g}-{m['tau'][0]['ci95_s'][1]:.3g} "
                          f"(truth {m['tau'][0]['truth_s']:g}; one 2 N step, 20 mV drift)"},
        {"figure": "time constant, taxel 2 (s)", "thesis": th["tau_s"][1],
         "simulated rig": f"{m['tau'][1]['tau_s']:.4g}, 95 % {m['tau'][1]['ci95_s'][0]:.3g}-{m['tau'][1]['ci95_s'][1]:.3g} "
                          f"(truth {m['tau'][1]['truth_s']:g}; one 2 N step, 20 mV drift)"},
        {"figure": "linearity R (PZT)", "thesis": th["linearity_R"]["PZT"],
         "simulated rig": f"{min(R):.4g}-{max(R):.4g} (9 taxels)"},
        {"figure": "repeatability (%)", "thesis": f"{th['repeatability_pct'][0]} / {th['repeatability_pct'][1]}",
         "simulated rig": f"{m['repeatability_pct']['by_spread']:.2f} (1 - std/mean), "
                          f"{m['repeatability_pct']['by_range']:.2f} (1 - range/mean)"},
        {"figure": "FRF RMS error, lumped (%)", "thesis": th["rms_error_pct"]["lumped"],
         "simulated rig": f"{m['rms_error_pct']['lumped']:.3g} over the coherent band (as the thesis); on the "
                          f"validation half {m['calibration']['rms_before_pct']:.3g} before and "
                          f"{m['calibration']['rms_after_pct']:.3g} after calibration"},
        {"figure": "FRF RMS error, FEM (%)", "thesis": th["rms_error_pct"]["FEM"],
         "simulated rig": (f"{m['rms_error_pct']['fem']:.1f} (the simulated taxel is the lumped model)"
                           if m["rms_error_pct"].get("fem") is not None else "not computed")},
        {"figure": "FRF RMS error, FEM-simulated taxel (%)", "thesis": "-",
         "simulated rig": f"lumped {m['rms_error_pct_fem_rig']['lumped']:.1f}, FEM "
                          f"{m['rms_error_pct_fem_rig']['fem']:.2f}"},
        *([{"figure": "FRF RMS error, reduced-model taxel: FEM truth (%)", "thesis": "-",
            "simulated rig": "lumped (seed's) {lumped:.1f}, lumped (FEM-informed) {lumped_fem:.1f}, FEM {fem:.1f} "
                             "before calibration; calibrated on the reduced model: gain {g:.4g} (95 % {g0:.4g}-{g1:.4g}, "
                             "truth {gt:.4g}), time-constant scale {s:.4g} (95 % {s0:.4g}-{s1:.4g}, truth {st:.4g}), "
                             "validation RMS {rb:.2f} -> {ra:.2f}".format(
                                 **m["rms_error_pct_reduced_rig"], g=m["calibration_reduced"]["gain"],
                                 g0=m["calibration_reduced"]["gain_ci95"][0], g1=m["calibration_reduced"]["gain_ci95"][1],
                                 gt=v["truth"]["reduced_rig"]["gain_factor"], s=m["calibration_reduced"]["tau_scale"],
                                 s0=m["calibration_reduced"]["tau_scale_ci95"][0],
                                 s1=m["calibration_reduced"]["tau_scale_ci95"][1],
                                 st=v["truth"]["reduced_rig"]["tau_factor"],
                                 rb=m["calibration_reduced"]["rms_before_pct"],
                                 ra=m["calibration_reduced"]["rms_after_pct"])}]
           if m.get("rms_error_pct_reduced_rig") and m.get("calibration_reduced") else []),
        *([{"figure": "silicone modulus scale / loss factor", "thesis": "not identified",
            "simulated rig": f"{m['silicone']['modulus_scale']:.4g} / {m['silicone']['loss_factor']:.3g} from a chirp "
                             f"with the travel (truth {v['truth']['silicone']['modulus_scale']:g} / "
                             f"{v['truth']['silicone']['loss_factor']:g}); the bench chirp alone: Cramer-Rao "
                             f"{m['silicone']['identifiability']['bench_chirp']['cramer_rao_sd_pct'][0]:.0f} % / "
                             f"{m['silicone']['identifiability']['bench_chirp']['cramer_rao_sd_pct'][1]:.0f} % at 1 %"}]
           if m.get("silicone") else []),
        {"figure": "localization, largest taxel", "thesis": "PZT better than PVDF",
         "simulated rig": f"{100 * loc['correct_rate']:.0f} % of the {loc['presses']} presses matched to a taxel "
                          f"(the localization table lists all {_all_presses(v)} presses by where they land)"},
        {"figure": "localization, model-based", "thesis": "-",
         "simulated rig": f"{loc['model_position_error_mm_rms']:.3g} mm, force {loc['model_force_error_pct_rms']:.3g} % rms"
                          + (f" on taxels; between them {loc['model_based']['between']['position_error_mm_rms']:.3g} mm "
                             f"rms (median {loc['model_based']['between'].get('position_error_mm_median', float('nan')):.3g} mm),"
                             f" force {loc['model_based']['between']['force_error_pct_rms']:.3g} % "
                             f"(largest taxel: {loc['largest_taxel']['between']['position_error_mm_rms']:.3g} mm)"
                             if loc.get("model_based", {}).get("between", {}).get("presses") else "")},
        {"figure": f"localization, predicted (Cramer-Rao, {noise})", "thesis": "-",
         "simulated rig": f"{loc['predicted_position_error_mm_at_taxels']:.3g} mm at the taxels, "
                          f"{loc['predicted_position_error_mm_max']:.3g} mm worst"},
    ]


def _silicone_rows(v: dict) -> list[dict]:
    """The silicone and piezo scales of the travel chirp (when the loop recorded one)."""
    sil, cal, t = v["measured"].get("silicone"), v["measured"]["calibration"], v["truth"].get("silicone", {})
    if not sil:
        return []
    return [{"parameter": "silicone modulus scale (travel chirp)", "value": sil["modulus_scale"],
             "95 % low": sil["modulus_scale_ci95"][0], "95 % high": sil["modulus_scale_ci95"][1],
             "truth": t.get("modulus_scale")},
            {"parameter": "silicone loss factor (travel chirp)", "value": sil["loss_factor"],
             "95 % low": sil["loss_factor_ci95"][0], "95 % high": sil["loss_factor_ci95"][1],
             "truth": t.get("loss_factor")},
            {"parameter": "piezo coefficient scale (= g)", "value": cal["gain"], "95 % low": cal["gain_ci95"][0],
             "95 % high": cal["gain_ci95"][1], "truth": v["truth"].get("gain_factor")}]


def build_page(folder: Path, out: Path) -> Page:
    """Write OUT/<folder name>.html for a validation folder; returns its Page (index card numbers)."""
    folder = Path(folder)
    v = json.loads((folder / "validation.json").read_text())
    cal = v["measured"]["calibration"]
    cal_rows = [{"parameter": "charge gain g", "value": cal["gain"], "95 % low": cal["gain_ci95"][0],
                 "95 % high": cal["gain_ci95"][1], "truth": v["truth"].get("gain_factor")},
                {"parameter": "chain tau scale s", "value": cal["tau_scale"], "95 % low": cal["tau_scale_ci95"][0],
                 "95 % high": cal["tau_scale_ci95"][1], "truth": v["truth"].get("tau_factor")},
                *_silicone_rows(v),
                {"parameter": "lumped FRF RMS error, validation half, before (%)", "value": cal["rms_before_pct"]},
                {"parameter": "lumped FRF RMS error, validation half, after (%)", "value": cal["rms_after_pct"]}]
    rows = summary_rows(v, _noise(folder))
    frf_png = _png_bytes(_frf_figure(folder))
    fb, vb = cal["fit_band_Hz"], cal["validation_band_Hz"]
    sections = [
        {"title": "Summary beside the thesis", "blocks": [
            {"type": "table", "table": table(rows, ["figure", "thesis", "simulated rig"],
                                             title="summary beside the thesis")},
            {"type": "note", "text": "Thesis column: the thesis's own bench figures (chapter 4). Measured on the "
                                     "simulated rig: each record captured over a "
                                     "pseudo-terminal, analysed with taxel measure analyze/calibrate/localize. Model: "
                                     "the lumped 3-DoF model of the thesis PZT taxel through the bench's readout."}]},
        {"title": "Step responses", "blocks": [_figure(_png_bytes(_step_figure(folder)),
                                                       "Step responses through the 500 MΩ input: each measured "
                                                       "trace and its first-order fit (time constant in the legend).")]},
        {"title": "Frequency response", "blocks": [_figure(frf_png, "Measured frequency response (H1 and the "
                                                           "amplitude-spectrum ratio) against the lumped model before "
                                                           "and after calibration, and the coherence (0.9 drawn).")]},
        {"title": "Linearity and repeatability", "blocks": [_figure(
            _png_bytes(_linearity_figure(folder)), "Left: voltage peak against force peak per taxel (linearity R). "
                                                   "Right: the peaks of repeated impulses (repeatability).")]},
        {"title": "Localization", "blocks": [_figure(
            _png_bytes(_localization_figure(folder)),
            f"Left: which taxel read largest against which was pressed. Right: the predicted (Cramer-Rao) position "
            f"error at {_noise(folder)}, with the pressed points and the model-based estimates."), {
            "type": "table", "table": table(localization_rows(folder), ["method", "presses", "n",
                                                                       "position error rms (mm)",
                                                                       "position error median (mm)",
                                                                       "position error max (mm)",
                                                                       "force error rms (%)"])}]},
        {"title": f"Calibration (chirp; fitted on {fb[0]:g}-{fb[1]:g} Hz, validated on {vb[0]:g}-{vb[1]:g} Hz)",
         "blocks": [{"type": "table", "table": table(cal_rows, ["parameter", "value", "95 % low", "95 % high",
                                                                "truth"])}]},
        {"title": "Provenance", "blocks": provenance(folder, None)},
    ]
    m = v["measured"]
    from taxel.reports.page import Headline
    lumped = "lumped 3-DoF model against the simulated rig"
    numbers = [Headline("time constants", f"{m['tau'][0]['tau_s']:.3g} s, {m['tau'][1]['tau_s']:.3g} s",
                        "first-order fits to the measured steps"),
               Headline(f"FRF RMS error, lumped, {vb[0]:g}-{vb[1]:g} Hz", f"{cal['rms_before_pct']:.3g} % → "
                        f"{cal['rms_after_pct']:.3g} % after calibration", lumped),
               Headline("localization, largest taxel", f"{100 * m['localization']['correct_rate']:.0f} % of "
                        f"{m['localization']['presses']} matched presses", "measured peaks, no model")]
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{folder.name}.html"
    title = f"{folder.name} (validation)"
    from taxel.reports.tables import write_csvs
    write_csvs(sections, out, folder.name)
    path.write_text(templates().get_template("page.html").render(
        title=title, kind="validation", folder=folder.name, banners=[], headline=numbers, sections=sections),
        encoding="utf-8")
    return Page(path, "validation", title, numbers, [], frf_png)
