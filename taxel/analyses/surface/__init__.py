"""The surface of a design, mapped: the 3D surface map by reciprocity (surface_map:
every taxel's response to a force anywhere on the top; map_metrics: coverage, its 3D
minimum and dead zones, the localization error's rms, 95th percentile and worst case,
crosstalk; probe_map: the rig's probe on Yeoh as a correction of it), the 2D section's
influence functions of a press position (influence), coverage and its dead zone on
them (coverage), the predicted localization error (localization), and the taxel models
behind the simulated bench (bench_model).

A function named as its module (`influence`, `coverage`) is reached through its
module (`taxel.analyses.surface.influence.influence`).
"""

from taxel.analyses.surface.bench_model import compliance, fem_charges, loss_factor, scaled_model
from taxel.analyses.surface.coverage import SIGMAS, Coverage, best_peak, design_coverage
from taxel.analyses.surface.influence import Influence, samples
from taxel.analyses.surface.map_metrics import MapCoverage, MapLocalization, crosstalk_matrix, sensing_area
from taxel.analyses.surface.probe_map import factor_error, press_factor, probe_correction
from taxel.analyses.surface.surface_map import Footprint, ProbeCorrection, SurfaceMap, map_scene, patch_quadrature
from taxel.analyses.surface.localization import (NOISE_V, AccuracyMap, LocalizationError, accuracy_map,
                                                 localization_error, localization_error_of)

__all__ = ["Influence", "samples", "Coverage", "best_peak", "design_coverage", "SIGMAS", "AccuracyMap",
           "LocalizationError", "accuracy_map", "localization_error", "localization_error_of", "NOISE_V",
           "scaled_model", "compliance", "loss_factor", "fem_charges", "SurfaceMap", "Footprint", "ProbeCorrection",
           "map_scene", "patch_quadrature", "MapCoverage", "MapLocalization", "crosstalk_matrix", "sensing_area",
           "probe_correction", "press_factor", "factor_error"]
