#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""gf_relay: a fault-injecting LCM relay between two LCM URLs.

    gf_relay.py --in URL --out URL --log FILE [--seed S] [--drop P] [--dup P]
                [--reorder P] [--delay P] [--delay-ms MS] [--channels REGEX]

Subscribes to the simulators' inputs (GF_(MEAS|CTRL)_<n>) on --in and
republishes them on --out, with seeded faults decided per message in
arrival order:
  drop     the message is not forwarded at all (lost on the wire)
  dup      a second copy is forwarded, after 0..MS ms
  reorder  the message is held until 1..3 later messages have gone out
  delay    the message is held for 1..MS ms (others overtake it)
(this kernel has no netem qdisc: the relay is the faulty network).

SIGUSR1 pauses forwarding (messages are still read and queued), SIGUSR2
resumes it: the network tests pause the wire around a node restart so
that the split of the stream between the two node processes is exact.
SIGTERM forwards what is still held, writes the log and ends with a
summary line. The log has one line per event, in the order of the wire:
  fwd KIND TRACK SESSION SEQ UTIME COPY   (COPY 1 = original, 2 = duplicate)
  drop KIND TRACK SESSION SEQ UTIME
  pause / resume
"""
import argparse
import heapq
import random
import signal
import sys
import time

import lcm
from gaussfilt_lcm import control_t, measurement_t

state = {"stop": False, "paused": False, "marks": []}


def on_signal(sig, _frame):
    if sig == signal.SIGTERM or sig == signal.SIGINT:
        state["stop"] = True
    elif sig == signal.SIGUSR1:
        state["marks"].append("pause")
    elif sig == signal.SIGUSR2:
        state["marks"].append("resume")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--in", dest="url_in", required=True)
    ap.add_argument("--out", dest="url_out", required=True)
    ap.add_argument("--log", required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--drop", type=float, default=0.0)
    ap.add_argument("--dup", type=float, default=0.0)
    ap.add_argument("--reorder", type=float, default=0.0)
    ap.add_argument("--delay", type=float, default=0.0)
    ap.add_argument("--delay-ms", type=float, default=20.0)
    ap.add_argument("--channels", default="GF_(MEAS|CTRL)_-?[0-9]+")
    a = ap.parse_args()

    rng = random.Random(a.seed)
    lin, lout = lcm.LCM(a.url_in), lcm.LCM(a.url_out)
    log = []
    n = {"in": 0, "drop": 0, "dup": 0, "reorder": 0, "delay": 0, "out": 0}
    timed = []  # heap of (due, order, channel, data, info, copy)
    held = []  # reordered: [messages still to pass, channel, data, info]
    order = [0]

    def send(channel, data, info, copy):
        lout.publish(channel, data)
        log.append("fwd %s %d" % (info, copy))
        n["out"] += 1
        for h in held:  # every message out lets held ones move up
            h[0] -= 1

    def flush(now, everything=False):
        while True:
            sent = False
            while held and (everything or held[0][0] <= 0):
                _, ch, data, info = held.pop(0)
                send(ch, data, info, 1)
                sent = True
            while timed and (everything or timed[0][0] <= now):
                _, _, ch, data, info, copy = heapq.heappop(timed)
                send(ch, data, info, copy)
                sent = True
            if not sent:
                return

    def later(delay_s, channel, data, info, copy):
        order[0] += 1
        heapq.heappush(timed, (time.monotonic() + delay_s, order[0], channel,
                               data, info, copy))

    def on_msg(channel, data):
        kind = "meas" if channel.startswith("GF_MEAS_") else "ctrl"
        try:
            m = (measurement_t if kind == "meas" else control_t).decode(data)
            info = "%s %d %d %d %d" % (kind, m.track, m.session, m.seq, m.utime)
        except ValueError:
            info = "%s ? ? ? ?" % kind
        n["in"] += 1
        r = rng.random()
        if r < a.drop:
            n["drop"] += 1
            log.append("drop " + info)
            return
        r -= a.drop
        if r < a.dup:
            n["dup"] += 1
            later(rng.uniform(0.0, a.delay_ms) / 1e3, channel, data, info, 2)
        elif r < a.dup + a.reorder:
            n["reorder"] += 1
            held.append([rng.randint(1, 3), channel, data, info])
            return
        elif r < a.dup + a.reorder + a.delay:
            n["delay"] += 1
            later(rng.uniform(1.0, a.delay_ms) / 1e3, channel, data, info, 1)
            return
        if state["paused"]:
            later(0.0, channel, data, info, 1)
        else:
            send(channel, data, info, 1)

    lin.subscribe(a.channels, on_msg).set_queue_capacity(100000)
    for s in (signal.SIGTERM, signal.SIGINT, signal.SIGUSR1, signal.SIGUSR2):
        signal.signal(s, on_signal)
    print("gf_relay: ready in=%s out=%s seed=%d drop=%g dup=%g reorder=%g "
          "delay=%g delay_ms=%g" % (a.url_in, a.url_out, a.seed, a.drop, a.dup,
                                    a.reorder, a.delay, a.delay_ms), flush=True)
    while not state["stop"]:
        try:
            lin.handle_timeout(2)
        except OSError:  # a signal interrupted the wait
            time.sleep(0.001)  # (its handler runs right after)
        while state["marks"]:
            mark = state["marks"].pop(0)
            state["paused"] = mark == "pause"
            log.append(mark)
        if not state["paused"]:
            flush(time.monotonic())
    # Drain what the socket still holds, then everything held back.
    while lin.handle_timeout(100) > 0:
        pass
    flush(0.0, everything=True)
    with open(a.log, "w") as f:
        f.write("\n".join(log) + "\n")
    print("gf_relay: summary in=%d dropped=%d duplicated=%d reordered=%d "
          "delayed=%d out=%d" % (n["in"], n["drop"], n["dup"], n["reorder"],
                                 n["delay"], n["out"]), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
