"""The thesis-model study beside linear silicone in the report (reports.thesis_model):
per piezo and force, the Yeoh points solved and stopped short, their last converged
force, and Yeoh / linear - 1 of the figure's output, on rows shaped as
studies.store.tidy_rows writes them."""

from taxel.reports import thesis_model as T
from taxel.reports.figures import pyplot


def _rows():
    rows = []
    for k, (lin, yeoh, stop) in {"1 mm": (0.80, 0.84, None), "2 mm": (0.60, 0.66, 0.45)}.items():
        rows.append({"piezo": "PZT", "silicone_thickness": k, "force": "1 N", "silicone": "linear",
                     "status": "done", "sensitivity": -lin, "crosstalk": 0.1})
        y = {"piezo": "PZT", "silicone_thickness": k, "force": "1 N", "silicone": "Yeoh (thesis)",
             "status": "done", "sensitivity": -yeoh, "crosstalk": 0.08}
        if stop:
            y["stopped_at"] = stop
        rows.append(y)
    return rows


def test_the_comparison_counts_stopped_points_and_compares_each_point(tmp_path):
    rows = _rows()
    assert T.is_thesis_model(rows) and not T.is_thesis_model([r for r in rows if r["silicone"] == "linear"])
    assert T.swept(rows) == "silicone_thickness" and T.output(rows) == "sensitivity"
    (c,) = T.comparison(rows)
    assert (c["Yeoh points"], c["solved to the force"], c["stopped short"]) == (2, 1, 1)
    assert c["last converged force (N)"] == "0.45-0.45"
    assert c["Yeoh / linear - 1 of sensitivity, median (%)"] == "+7.5"        # +5 % and +10 %
    assert c["range (%)"] == "+5.0 to +10.0"
    assert "1 stopped short" in T.sentence(rows) and "2 Yeoh points with a result, 1 of them at their force" in T.sentence(rows)
    png = T.draw(rows, tmp_path, "fig")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_figure_draws_linear_dashed_yeoh_solid_and_stopped_points_as_crosses():
    """What the figure plots, read from its lines: linear |V|/F dashed at both thicknesses,
    the Yeoh point solved to its force on the solid line, the stopped one a cross at its
    own value (0.66 V/N at 2 mm), not joined to the solved ones."""
    fig = T.figure(_rows(), "fig")
    (ax,) = fig.axes
    lines = {(ln.get_linestyle(), ln.get_marker()): ln for ln in ax.get_lines() if len(ln.get_xdata())}
    lin, yeoh, stop = lines["--", "o"], lines["-", "o"], lines["None", "x"]
    assert list(lin.get_xdata()) == [1.0, 2.0] and list(lin.get_ydata()) == [0.80, 0.60]
    assert list(yeoh.get_xdata()) == [1.0] and list(yeoh.get_ydata()) == [0.84]
    assert list(stop.get_xdata()) == [2.0] and list(stop.get_ydata()) == [0.66]
    assert ax.get_ylabel().startswith("sensitivity") and "PZT" in ax.get_title()
    pyplot().close(fig)


def test_a_gap_sweep_shows_crosstalk():
    rows = [{("gap" if k == "silicone_thickness" else k): v for k, v in r.items()} for r in _rows()]
    assert T.swept(rows) == "gap" and T.output(rows) == "crosstalk"
    (c,) = T.comparison(rows)
    assert c["Yeoh / linear - 1 of crosstalk, median (%)"] == "-20.0"             # 0.08 against 0.1
