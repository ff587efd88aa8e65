"""The surface of a design, mapped: influence functions of a press position
(influence), coverage and its dead zone (coverage), the predicted localization error
(localization), and the taxel models behind the simulated bench (bench_model).

A function named as its module (`influence`, `coverage`) is reached through its
module (`taxel.analyses.surface.influence.influence`).
"""

from taxel.analyses.surface.bench_model import compliance, fem_charges, loss_factor, scaled_model
from taxel.analyses.surface.coverage import SIGMAS, Coverage, best_peak, design_coverage
from taxel.analyses.surface.influence import Influence, samples
from taxel.analyses.surface.localization import (NOISE_V, AccuracyMap, LocalizationError, accuracy_map,
                                                 localization_error, localization_error_of)

__all__ = ["Influence", "samples", "Coverage", "best_peak", "design_coverage", "SIGMAS", "AccuracyMap",
           "LocalizationError", "accuracy_map", "localization_error", "localization_error_of", "NOISE_V",
           "scaled_model", "compliance", "loss_factor", "fem_charges"]
