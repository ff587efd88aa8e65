"""Mirror symmetry: a half or quarter model that answers for the full one.

A layout cut by meshing.layout.cut keeps x >= 0 (plane 0) and/or y >= 0 (plane 1)
of a sensor that is mirror symmetric about those planes: geometry, materials
(poled along z, so a mirror across a vertical plane maps the piezo law onto
itself), supports, load and electrode states. The mirror group G (|G| = 2 or 4)
splits every field of the full model into classes, one per character chi (a sign
per plane): u_n(-x) = -chi u_n(x) for the component normal to a plane,
u_t(-x) = chi u_t(x) for the others, and p, phi even (chi = +1) or odd (chi = -1).
On the cut part each class is a boundary-value problem with these conditions on
the plane:

    chi = +1 (symmetric):     u.n = 0;          phi and p free (natural: D.n = 0)
    chi = -1 (antisymmetric): u x n = 0;        phi = 0, p = 0, u.n free

The weak form is the full one restricted to the cut part: the work of a symmetric
field over the full body is |G| times its work over the cut part, so the load is
applied as F / |G| (a load patch is centred on the planes, so the piece of it that
is modelled carries the share F / |G| of its force) and energies are 1 / |G| of
the full model's.

Electrodes. A taxel wholly inside the modelled part stands for its m mirror
images (its orbit); one cut by s_a planes is modelled by 1 / s_a of it, and
s_a m = |G|. In a class chi an electrode cut by a plane with sign -1 is at 0 V
(phi is odd there). With V and Q the full model's voltages and charges, the
modelled electrode a carries q_a = Q_i / s_a (i any of its images) and

    q_a = sum_b Cred^chi[a, b] V_b,   Cred^chi[a, b] = (1 / s_a) sum_{j in orbit b} chi(g_j) C[i_a, j]

where g_j maps b onto j. Inverting the transform over G gives the full Maxwell
capacitance matrix from the class matrices:

    C[g1 a, g2 b] = (1 / m_b) sum_chi chi(g1 g2) s_a Cred^chi[a, b]

(the sum runs over the classes where a and b both float). The press is symmetric,
so the voltages, charges and short-circuit charges of the full model are those of
the symmetric class (charges times s_a); only the capacitance needs the other
classes (one extra factorization per class with a floating electrode in it: none
for a single centred taxel).

What a symmetric solve reports: every electrode of the full array (the mirror
images of each modelled taxel get its voltage and s_a times its charge, and their
own row of the full capacitance matrix), the full applied force and support
reaction (|G| times the modelled ones; the components normal to a cut plane are
zero by symmetry), and the fields of the modelled part only (its mesh).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from taxel.fem.assembly import System
from taxel.fem.assembly import supports
from taxel.meshing.layout import group

__all__ = ["MirrorClass", "capacitance", "classes", "group", "symmetry_order", "unfold_electrodes", "unfold_reaction"]


@dataclass(frozen=True)
class MirrorClass:
    """One antisymmetric class: its signs (one per plane), the DOFs it holds at zero
    (supports, u x n on its odd planes, p and phi there) and the electrodes it grounds."""

    signs: tuple[int, ...]
    fixed: np.ndarray
    grounded: tuple[str, ...]


def symmetry_order(sy: System) -> int:
    """|G|: how many copies of the modelled part make the full sensor."""
    return 2 ** len(sy.tm.layout.planes)


def _flip(planes, k):
    return tuple(-1 if q == k else 1 for q in planes)


def _character(signs, g) -> int:
    return int(np.prod([s if gi < 0 else 1 for s, gi in zip(signs, g)]))


def classes(sy: System) -> list[MirrorClass]:
    """The antisymmetric classes that have a floating electrode (their capacitance
    couples the full model's mirror images of a taxel)."""
    lay, tm = sy.tm.layout, sy.tm
    ub = next(iter(sy.ubases.values()))
    images = lay.images
    out = []
    for signs in group(lay.planes)[1:]:
        odd = [k for k, s in zip(lay.planes, signs) if s < 0]
        fixed = [supports(sy.problem, ub, signs)]
        grounded = set()
        for k in odd:
            facets = tm.facets.get("mirror_" + "xy"[k], np.zeros(0, int))
            for region, pb in sy.pbases.items():
                fixed.append(sy.offsets[("p", region)].start + pb.get_dofs(facets).all())
            for pb in sy.phibases.values():
                fixed.append(sy.offsets["phi"].start + pb.get_dofs(facets).all())
            g = _flip(lay.planes, k)       # cut by plane k: no separate mirror image across it
            models = {model for _, model, _ in images}
            grounded |= models - {model for _, model, h in images if h == g}
        floating = [k for k, s in sy.electrodes.states.items() if s != "reference" and k not in grounded]
        if floating:
            out.append(MirrorClass(signs, np.unique(np.concatenate(fixed)).astype(int), tuple(sorted(grounded))))
    return out


def capacitance(sy: System, blocks: dict) -> tuple[list[str], np.ndarray]:
    """The full model's capacitance matrix (its non-reference electrodes, in the full
    layout's order) from each class's modelled one: blocks[signs] = (names, Cred)."""
    lay = sy.tm.layout
    G = symmetry_order(sy)
    states = sy.electrodes.states
    rows = [(full, model, g) for full, model, g in lay.images if states.get(model) != "reference"]
    m = {}
    for _, model, _ in lay.images:
        m[model] = m.get(model, 0) + 1
    C = np.zeros((len(rows), len(rows)))
    for chi, (names, Cred) in blocks.items():
        pos = {k: i for i, k in enumerate(names)}
        for i, (_, a, g1) in enumerate(rows):
            if a not in pos:
                continue
            for j, (_, b, g2) in enumerate(rows):
                if b in pos:
                    g = tuple(x * y for x, y in zip(g1, g2))
                    C[i, j] += _character(chi, g) * (G / m[a]) * Cred[pos[a], pos[b]] / m[b]
    return [r[0] for r in rows], C


def unfold_electrodes(sy: System, electrodes: dict, C: np.ndarray, names: list[str]) -> dict:
    """Every electrode of the full array from the modelled ones (ElectrodeResult
    objects of fem.static): mirror images get the voltage, s_a times the charges,
    and their own diagonal of the full capacitance matrix."""
    lay = sy.tm.layout
    G = symmetry_order(sy)
    m = {}
    for _, model, _ in lay.images:
        m[model] = m.get(model, 0) + 1
    pos = {k: i for i, k in enumerate(names)}
    out = {}
    for full, model, _ in lay.images:
        e = electrodes[model]
        s = G / m[model]
        out[full] = replace(e, name=full, charge=s * e.charge, short_circuit_charge=s * e.short_circuit_charge,
                            capacitance=float(C[pos[full], pos[full]]) if full in pos else e.capacitance)
    return out


def unfold_reaction(sy: System, reaction: np.ndarray) -> np.ndarray:
    """The full support reaction: |G| times the modelled one, zero normal to the planes."""
    out = symmetry_order(sy) * np.asarray(reaction, dtype=float)
    for k in sy.tm.layout.planes:
        out[k] = 0.0
    return out
