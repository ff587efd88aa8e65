"""The bench's data in and out: the wire protocols (protocol), the rig file (rig),
the measurement folder (folder), capture from a serial port (capture), import of
lab files (importers), CSV export (export), and the simulated rig (signals: what
the models make; simulated_run: a run and its byte stream;
wire: corruption and the pty / TCP player). The analysis of what was measured is
studies.measured; the models' predictions are taxel.analyses (crosstalk,
influence, localization, bench_model)."""
