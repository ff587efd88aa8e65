"""Result objects of the analyses, one protocol for all (results.base):
`record()`, `summary()`, `to_folder(dir)`, `error` and `outputs()`; `read(folder)`
reads a folder's result.json back into the same type. The CLI, studies and
reports read these and never re-derive what a result holds."""

from taxel.analyses.results.dynamic import FrequencyResult, LumpedResult, TransientResult
from taxel.analyses.results.base import (KINDS, MEMBERS, NOT_ESTIMATED, OUTPUT_NAMES,
                                         AnalysisResult, ErrorEstimate, OutputError)
from taxel.analyses.results.base import FORMAT, write_csv, write_scene
from taxel.analyses.results.noise import NoiseResult
from taxel.analyses.results.outputs import OUTPUTS, Output, table
from taxel.analyses.results.static import StaticResult, Stop
from taxel.analyses.results.stored import RESULT_TYPES, ResultError, read, read_record, result_kind

__all__ = ["FrequencyResult", "LumpedResult", "TransientResult", "StaticResult", "Stop", "ErrorEstimate", "OutputError",
           "OUTPUT_NAMES", "NOT_ESTIMATED", "FORMAT", "write_csv",
           "write_scene", "KINDS", "MEMBERS", "AnalysisResult", "OUTPUTS", "Output", "table", "RESULT_TYPES",
           "ResultError", "read", "read_record", "result_kind", "NoiseResult"]
