"""Does the stream match the rig file? Checked on the first frames of a capture.

A rig file that names the wrong protocol or lists a different number of channels
than the stream carries decodes no frame at all: every packet fails its length,
COBS or checksum test. Rather than write garbage counters for a whole capture,
the capture stops after the first `FIRST_FRAMES` failed packets with no good one,
and `diagnose` says what the bytes are: the other protocol, the channel count
they carry, or nothing recognisable (a wrong baud rate, another device).
"""

from __future__ import annotations

from taxel.studies.bench.protocol import MAX_CHANNELS, PROTOCOLS, decode_all

FIRST_FRAMES = 20        # failed packets, with none decoded, before a capture is refused
HEAD_BYTES = 1 << 16     # the first bytes of a stream kept for the diagnosis
# no frame in this many bytes: 10 times the longest frame (32 channels in taxel-ascii,
# about 400 bytes); a stream without the rig protocol's delimiter fails no packet at all
NO_FRAME_BYTES = 4096


class StreamMismatch(ValueError):
    """The stream contradicts the rig file; one line naming the key to fix."""


def mismatched(counters) -> bool:
    """True when the first packets all failed (FIRST_FRAMES drops and no frame), or
    NO_FRAME_BYTES arrived without a frame."""
    return counters.frames == 0 and (counters.dropped >= FIRST_FRAMES or counters.bytes >= NO_FRAME_BYTES)


def diagnose(head: bytes, protocol: str, n: int, source: str) -> str:
    """One line: what the first bytes of a stream are, against the rig's protocol
    and channel count n (every protocol and channel count is tried; the one that
    decodes most frames is named)."""
    best = (0, None, None)
    for proto in PROTOCOLS:
        for k in range(1, MAX_CHANNELS + 1):
            frames, _ = decode_all(head, proto, k)
            if len(frames) > best[0]:
                best = (len(frames), proto, k)
    got, proto, k = best
    _, c = decode_all(head, protocol, n)
    seen = (f"none of the first {len(head)} bytes ({c.dropped} packets) decodes as {protocol} with {n} "
            f"channels ({c.length_failures} wrong length or channel count, {c.cobs_failures} unreadable, "
            f"{c.crc_failures} bad checksums)")
    if proto is None:
        fix = ("the bytes are no taxel protocol at any channel count: check port.baud and that the port is "
               "the rig's")
    elif proto != protocol and k == n:
        fix = f"the stream is {proto}: set port.protocol = \"{proto}\" in the rig file"
    elif proto == protocol:
        fix = (f"the stream carries {k} channels per frame: list {k} [[channels]] in the rig file "
               f"(it lists {n})")
    else:
        fix = (f"the stream is {proto} with {k} channels per frame: set port.protocol = \"{proto}\" and list "
               f"{k} [[channels]] in the rig file")
    return f"{source}: the stream contradicts the rig file: {seen}; {fix}. Nothing was kept"
