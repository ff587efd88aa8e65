"""The mesh a scene without `mesh.size` gets (taxel.scene.DEFAULT_MESH, measured by
benchmarks/default_mesh.py): per model type, re-chosen when `replace` changes the
type, and never over a size the scene gives."""

from __future__ import annotations

import pytest

from taxel.scene import DEFAULT_MESH, load


def bare(model):
    sc = load("thesis-pzt-single-2d").replace(**{"model.type": model, "model.depth": None})
    return sc.replace(**{"mesh.size": None, "mesh.piezo_size": None})


@pytest.mark.parametrize("model", sorted(DEFAULT_MESH))
def test_each_model_type_gets_its_default(model):
    m = bare(model).mesh
    size, piezo = DEFAULT_MESH[model]
    assert m.size == pytest.approx(size)
    assert (m.piezo_size or m.size / 4) == pytest.approx(piezo or size / 4)


def test_a_changed_model_type_gets_its_own_default_and_given_sizes_stay():
    sc = bare("plane_strain")
    assert sc.replace(**{"model.type": "3d", "model.depth": None}).mesh.size == pytest.approx(DEFAULT_MESH["3d"][0])
    back = sc.replace(**{"model.type": "3d", "model.depth": None}).replace(**{"model.type": "plane_strain"})
    assert back.mesh.size == pytest.approx(DEFAULT_MESH["plane_strain"][0]) and back.mesh.piezo_size is None
    given = load("thesis-pzt-single-3d")                   # its own [mesh]: 1 mm / 0.4 mm
    moved = given.replace(**{"model.type": "plane_strain"})
    assert (moved.mesh.size, moved.mesh.piezo_size) == pytest.approx((1e-3, 0.4e-3))
    only_piezo = bare("3d").replace(**{"mesh.piezo_size": 2e-3})   # larger than the default size: size follows
    assert only_piezo.mesh.size >= only_piezo.mesh.piezo_size
