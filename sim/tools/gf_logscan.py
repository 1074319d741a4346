# SPDX-License-Identifier: MIT
"""The tracks of an LCM log and how many beliefs and truths each has, read
with Python's standard library alone (no lcm module, nothing to install),
so that scripts/plot can say what a log holds before it installs anything.

    python3 gf_logscan.py LOG

Prints one line per track with a belief or a truth: "TRACK BELIEFS
TRUTHS", by track. Exits 2 with a message if LOG is not an LCM log.

The log format (LCM's eventlog.c): events one after another, each a 28
byte big-endian header (the sync word 0xEDA1DA01, the event number
int64, the timestamp int64, the channel's length int32, the data's length
int32), the channel's name, then the data.
"""
import re
import struct
import sys
from collections import Counter

SYNC = 0xEDA1DA01
HEADER = struct.Struct(">IqqiI")
CHANNEL = re.compile(rb"GF_(BELIEF|TRUTH)_(-?[0-9]+)")


def scan(path):
    """{track: [beliefs, truths]}; raises ValueError if path is not a log."""
    counts = {"BELIEF": Counter(), "TRUTH": Counter()}
    with open(path, "rb") as f:
        data = f.read()
    pos = 0
    while pos + HEADER.size <= len(data):
        sync, _, _, clen, dlen = HEADER.unpack_from(data, pos)
        if sync != SYNC or clen < 0:
            if pos == 0:
                raise ValueError("not an LCM log (no sync word at its start)")
            break  # a truncated last event
        pos += HEADER.size
        m = CHANNEL.fullmatch(data[pos:pos + clen])
        if m:
            counts[m.group(1).decode()][int(m.group(2))] += 1
        pos += clen + dlen
    if pos == 0:
        raise ValueError("empty, not an LCM log")
    tracks = set(counts["BELIEF"]) | set(counts["TRUTH"])
    return {t: [counts["BELIEF"][t], counts["TRUTH"][t]] for t in tracks}


def main():
    if len(sys.argv) != 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0 if len(sys.argv) == 2 else 2)
    try:
        tracks = scan(sys.argv[1])
    except (OSError, ValueError) as e:
        print("%s: %s" % (sys.argv[1], e), file=sys.stderr)
        sys.exit(2)
    for t in sorted(tracks):
        print(t, *tracks[t])


if __name__ == "__main__":
    main()
