"""The wall-clock ceiling of the tests' waits.

Every wait in the tests is event-driven: a process exits, a row is stored, bytes
appear in a file, a line is printed. The ceiling only turns a hang into a
failure. A busy CI machine shared by several jobs runs many times slower than a
quiet one (`test_ctrl_c_stops_cleanly` once waited more than 10 s for a capture to
write its last HDF5 block after Ctrl-C), so a ceiling near the expected time fails
good code: CEILING is ten minutes, far beyond any wait that is not a hang.
"""

CEILING = 600.0       # seconds


def poll_until(predicate, what: str, proc=None, every: float = 0.05):
    """Event-driven wait: return as soon as `predicate()` is true; fail if the process
    `proc` ended first, or (a hang) after CEILING seconds."""
    import time
    end = time.monotonic() + CEILING
    while not predicate():
        if proc is not None and proc.poll() is not None:
            raise AssertionError(f"the process ended before {what}: {proc.communicate()}")
        if time.monotonic() > end:
            if proc is not None:
                proc.kill()
            raise AssertionError(f"no {what} within {CEILING:g} s")
        time.sleep(every)
