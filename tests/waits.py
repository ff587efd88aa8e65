"""The wall-clock ceiling of the tests' waits.

Every wait in the tests is event-driven: a process exits, a row is stored, bytes
appear in a file, a line is printed. The ceiling only turns a hang into a
failure. A busy CI machine shared by several jobs runs many times slower than a
quiet one (`test_ctrl_c_stops_cleanly` once waited more than 10 s for a capture to
write its last HDF5 block after Ctrl-C), so a ceiling near the expected time fails
good code: CEILING is ten minutes, far beyond any wait that is not a hang.
"""

CEILING = 600.0       # seconds
