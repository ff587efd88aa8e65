"""Measured data in: the wire protocols (protocol), the rig file (rig), the
measurement folder (folder), capture from a serial port (capture), import of lab
files (importers), CSV export (export), and the simulated rig (simulate, its
crosstalk weights, and wire: corruption and the pty / TCP player)."""
