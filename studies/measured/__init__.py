"""Analysis of measured data (a measurement folder from studies.bench): the record
and its events (events), the step fit (step), peaks, linearity and repeatability
(peaks), the frequency response (frf), one folder's analysis (analysis), the
readings and localization of press events (readings, localize), the calibration of
the chain (calibrate) and of the silicone (silicone), and the validation loop on
the simulated rig (pipeline)."""
