"""taxel skin: a designed taxel array as a simulator's sensor that outputs volts.

- `taxel.skin.model`: the skin file (`SkinModel`, .npz: layout, influence, dynamics,
  noise, saturation, provenance); numpy only.
- `taxel.skin.runtime`: `SkinRuntime`, the per-step sensor (contact forces and points
  on the skin -> each taxel's readout voltage); numpy only, no FEM, no simulator.
- `taxel.skin.build`: `build(scene)` makes a SkinModel from the FEM (taxel.analyses).
- `taxel.skin.mujoco`: the thin MuJoCo adapter (contacts on a skin body).
- `taxel.skin.dataset`: labelled presses and voltages (HDF5) and the model-based baseline.

Nothing is imported here, so `from taxel.skin.runtime import SkinRuntime` stays light.
"""
