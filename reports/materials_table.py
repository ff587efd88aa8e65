"""The material constants a scene's solve used, one row per material: the piezo's
d33, d31, g33, relative permittivity, stiffness c33, density and loss tangent; the
silicone's Young's modulus, Poisson ratio, bulk and shear moduli, density and Yeoh
coefficients; and each one's source (taxel.analyses.scene_materials)."""

from __future__ import annotations

from taxel.analyses import scene_materials
from taxel.reports import tables
from taxel.scene import scene_material_names

EPS0 = 8.8541878128e-12      # F/m


def materials_table(scene) -> dict:
    """The constants table of the scene's materials (report page's Scene section)."""
    mats = scene_materials(scene)
    rows = []
    for name in scene_material_names(scene):
        m = mats[name]
        row = {"material": name, "kind": m.kind}
        if hasattr(m, "d33"):
            s, d, eps_t = m.strain_charge()
            row.update({"d33 (pC/N)": f"{1e12 * d[2, 2]:.3g}", "d31 (pC/N)": f"{1e12 * d[2, 0]:.3g}",
                        "g33 (mV·m/N)": f"{1e3 * m.g33:.3g}", "εr33 (free)": f"{eps_t[2, 2] / EPS0:.4g}",
                        "c33 (GPa)": f"{1e-9 * m.c[2, 2]:.3g}", "tan δ": f"{m.tan_delta:.3g}"})
        else:
            row.update({"E (kPa)": f"{1e-3 * m.E:.3g}", "ν": f"{m.nu:.4f}", "μ (kPa)": f"{1e-3 * m.mu:.3g}",
                        "K (MPa)": f"{1e-6 * m.K:.3g}"})
            if m.yeoh:
                row["Yeoh C10, C20, C30 (kPa)"] = ", ".join(f"{1e-3 * c:.3g}" for c in m.yeoh)
        row["density (kg/m³)"] = f"{m.rho:.4g}"
        row["source"] = m.source
        rows.append(row)
    cols = list(dict.fromkeys(k for r in rows for k in r))
    return tables.table(rows, cols, title="material constants")
