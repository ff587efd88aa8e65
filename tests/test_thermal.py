"""Heat conduction through the stack (fem.thermal) against closed forms, its energy
balance, and the pyroelectric charge of a uniformly heated film.

The meshes are the scene's own (a plate scene's layers through taxel.analyses.mesh):
plane strain, axisymmetric and 3D. A column's side faces carry no surface, so heat
flows in 1D through the layers, as the closed forms assume."""

from __future__ import annotations

import numpy as np
import pytest

from taxel.analyses import mesh
from taxel.fem import constitution, thermal
from taxel.scene import load

SIL = constitution.get("Ecoflex-00-30")
PZT = constitution.get("PSI-5H4E")


def plate(layers, model="plane_strain", width=0.4e-3, size=None, piezo_layers=8):
    """A narrow column of `layers` (material, thickness; bottom first) in a plate scene
    (a plate meshes each layer with `piezo_layers` elements through it: a thick layer is
    given as several)."""
    shape = {"shape": "disk", "radius": width} if model == "axisymmetric" else {"width": width, "length": width}
    data = {"model": {"type": model}, "plate": {**shape, "layers": [{"material": m, "thickness": t} for m, t in layers]},
            "load": {"kind": "pressure", "pressure": 1e3},
            "mesh": {"size": size or width / 2, "piezo_layers": piezo_layers}}
    return mesh(load(data))


def heat_of(tm):
    return {r: thermal.Heat(constitution.get(tm.materials[r][0]).conductivity,
                            constitution.get(tm.materials[r][0]).rho * constitution.get(tm.materials[r][0]).specific_heat)
            for r in tm.regions}


def model_of(tm, order=2):
    kin = constitution.kinematics(tm.layout.model, tm.layout.depth)
    return thermal.ThermalModel(tm.mesh, tm.regions, heat_of(tm), kin, order)


def top_surface(tm, h, Tb):
    return thermal.Surface(tm.facets["top"], h, lambda t: Tb)


def at_height(model, z):
    """The temperature history (nt,) at height z on the column's axis (x = y = 0; r = 0.1 mm)."""
    dim = model.mesh.p.shape[0]
    point = np.zeros((dim, 1))
    point[0] = 1e-4
    point[-1] = z
    return lambda T: (model.probe(point) @ T.T).ravel()


@pytest.mark.parametrize("h", [np.inf, 300.0])
def test_semi_infinite_silicone(h):
    """A 6 mm silicone column (semi-infinite over 2 s: erfc(6 mm / (2 sqrt(alpha 2 s))) ~ 1e-10),
    its top at 34 C (h = inf: 1e9 W/(m^2 K)) or through h = 300 W/(m^2 K): the temperature 1 mm
    down against Carslaw and Jaeger within 1 % of the rise."""
    tm = plate([("Ecoflex-00-30", 0.5e-3)] * 12, size=0.1e-3)
    m = model_of(tm)
    T0, Tb = 295.15, 307.15
    t = np.linspace(0, 2.0, 201)
    c = thermal.conduct(m, t, [top_surface(tm, 1e9 if np.isinf(h) else h, Tb)], T0)
    alpha = SIL.conductivity / (SIL.rho * SIL.specific_heat)
    depth = 1e-3
    at = at_height(m, 6e-3 - depth)(c.T)
    for k in (50, 100, 200):
        fem = at[k] - T0
        ref = (Tb - T0) * thermal.semi_infinite(depth, t[k], SIL.conductivity, alpha, h)
        assert abs(fem - ref) <= 0.01 * abs(ref), (t[k], fem, ref)


@pytest.mark.parametrize("model", ["plane_strain", "axisymmetric", "3d"])
def test_two_layer_slab_at_the_film(model):
    """1 mm silicone on a 0.127 mm PSI-5H4E film, bottom insulated, top stepped 12 K: the
    film's mean temperature rise against the two-layer series within 1 % (at 0.5, 1, 3 s; the
    early 0.5 s, where the film has risen 1 %, sets the step: 6.25 ms gives 0.06 %, 25 ms 0.9 %,
    Crank-Nicolson's second order)."""
    size = 0.25e-3 if model != "3d" else 0.4e-3
    tm = plate([("PSI-5H4E", 0.127e-3)] + [("Ecoflex-00-30", 0.25e-3)] * 4, model, width=0.4e-3, size=size)
    m = model_of(tm)
    T0, Ts = 295.15, 307.15
    t = np.linspace(0, 3.0, 481)
    c = thermal.conduct(m, t, [top_surface(tm, 1e9, Ts)], T0)
    film = tm.regions["layer0"]
    fem = (thermal.mean_temperature(c, film) - T0) / (Ts - T0)
    ref = thermal.two_layer_film_mean(t[1:], 1e-3, SIL.conductivity, SIL.rho * SIL.specific_heat,
                                      0.127e-3, PZT.conductivity, PZT.rho * PZT.specific_heat)
    for tk in (0.5, 1.0, 3.0):
        k = int(np.argmin(abs(t - tk)))
        assert abs(fem[k] - ref[k - 1]) <= 0.01 * ref[k - 1], (tk, fem[k], ref[k - 1])


def test_energy_balance_and_rest():
    """The heat stored equals the heat in through the surfaces (to round-off), a contact
    on and off included; a body at the initial temperature stays there."""
    tm = plate([("PSI-5H4E", 0.127e-3), ("Ecoflex-00-30", 1e-3)], "axisymmetric", width=2e-3, size=0.5e-3)
    m = model_of(tm, order=2)
    t = np.linspace(0, 2.0, 41)
    touch = thermal.Surface(tm.facets["top"], 1000.0, lambda s: 307.15 + 0.5 * s, active=lambda s: s <= 1.0)
    air = thermal.Surface(np.r_[tm.facets["edges"], tm.facets["bottom"]], 10.0, lambda s: 295.15)
    for theta in (0.5, 1.0):
        c = thermal.conduct(m, t, [touch, air], 295.15, theta=theta)
        stored = c.stored()
        assert stored[-1] > 0
        assert np.allclose(stored, c.heat_in, rtol=1e-9, atol=1e-12 * abs(stored).max())
        assert stored[-1] < stored.max()       # the air cools it after the lift
    still = thermal.conduct(m, t, [air], 295.15)
    assert np.allclose(still.T, 295.15, rtol=0, atol=1e-9)


def test_pyro_charge_of_a_uniformly_heated_free_film_is_p_a_dt():
    """A free film uniformly heated by dT holds Q = -s p3 A dT on its top electrode, exactly
    (to round-off): a 4 x 4 mm PVDF film in 3D, and a disk of PSI-5H4E axisymmetric, poled up and down."""
    for model, mat, width in (("3d", "PVDF", 4e-3), ("axisymmetric", "PSI-5H4E", 2e-3)):
        tm = plate([(mat, 52e-6)], model, width=width, size=0.5e-3, piezo_layers=1)
        m = model_of(tm)
        area = width ** 2 if model == "3d" else np.pi * width ** 2
        p3 = constitution.get(mat).pyro
        T = np.full((2, m.n), 295.15)
        T[1] += 1.7
        c = thermal.Conduction(np.array([0.0, 1.0]), T, np.zeros(2), m)
        for s in (1, -1):
            q = thermal.pyro_charge(c, thermal.Film(tm.regions["layer0"], p3, s, 52e-6))
            assert q[1] == pytest.approx(-s * p3 * area * 1.7, rel=1e-12)
