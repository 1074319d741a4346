#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Prints gf_node's beliefs as they arrive, and plots one track.

    python examples/beliefs.py [--url URL] [--track N] [--plot FILE.png]
                               [--config FILE] [--count N] [--seconds S]
    python examples/beliefs.py --status [--url URL] [--track N]
                               [--count N] [--seconds S]

Subscribes to GF_BELIEF_<track> (every track by default) and prints a
ready line once it listens ("beliefs.py: ready ..."; `gf_sim --wait FILE`
waits for it), then one line per belief: track, seq, stage, status, the
mean and the standard deviations (square roots of the covariance's
diagonal), and the NIS of an update. At the end it says how many beliefs
it got, and how many of each track it missed (belief seqs never seen:
those published before it listened, or lost). With --plot, every state of
--track is drawn to FILE.png (matplotlib) over time (the beliefs' utime, in
seconds): the mean, its 2-sigma band, and the true state when the
simulator's groundtruth_t (GF_TRUTH_<track>) is on the wire too. Each
state is labelled with its name and unit: from --config, the gf_node
configuration whose model the track runs (its states = and units = lines,
or the axes of its motion = line: x vx y vy for cv cv, or for type =
generated the names and units its library's descriptor gives); else the
car's (position, velocity) and the robot's (x, y, theta in rad); else x0,
x1, ...

With --status it prints the nodes' status messages instead (node_status_t
on GF_NODE_STATUS, once a second from every node): a line per status
with the node's counters, then a line per track (only --track's with it):
its inputs, applied, gated and refused by reason, the last NIS and the
mean NIS since the node's previous status. --count then counts statuses.

Needs the lcm package and the types (the package gaussfilt_lcm, which
scripts/lcm.sh installs into the project's .venv). URL: LCM's, e.g.
udpm://239.255.76.67:7667?ttl=0, or file:///x.lcmlog?speed=0 to read a
log to its end. Ends after --count beliefs, --seconds without one, or
Ctrl-C.
"""
import argparse
import math
import os
import re
import select
import sys

import lcm
from gaussfilt_lcm import belief_t

STAGES = {0: "init", 1: "predict", 2: "update"}
TRUTH = "GF_TRUTH_"
# measurement_t.MODEL_*: a configuration's type, and the presets' states
KINDS = {"car": 1, "robot": 2, "linear": 3, "generated": 3}
PRESET = {1: (["position", "velocity"], ["", ""]),
          2: (["x", "y", "theta"], ["", "", "rad"])}


def read_config(path):
    """The models of a gf_node configuration (docs/node.md), in file order:
    [(name, {key: value})], each with what its base gives it (all but
    channels, as the node does)."""
    models, cur = [], None
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            head = re.fullmatch(r"\[model\s+(\S+)\]", line)
            if head:
                cur = {}
                models.append((head.group(1), cur))
            elif "=" in line and cur is not None:
                key, val = (x.strip() for x in line.split("=", 1))
                if key == "base":
                    base = dict(next((m for n, m in models
                                      if n == val), {}))
                    base.pop("channels", None)
                    cur.update(base)
                cur[key] = val
    return models


def axis_states(motion):
    """The states of a dt-built linear model, axis by axis: cv cv is
    x vx y vy, ca is x vx ax."""
    names = []
    for i, kind in enumerate(motion.split()):
        a = "xyz"[i] if i < 3 else "q%d" % (i + 1)
        names += [a, "v" + a] + (["a" + a] if kind == "ca" else [])
    return names


def library_states(path):
    """The states' names and units of a generated model's library
    (type = generated, library = PATH: its gf_codegen_exported, as
    gaussfilt.codegen writes it), or ([], []) if it cannot be read."""
    import ctypes

    class Model(ctypes.Structure):  # gf_codegen_model's first fields
        _fields_ = [("version", ctypes.c_uint), ("name", ctypes.c_char_p),
                    ("n", ctypes.c_uint), ("nu", ctypes.c_uint),
                    ("nparams", ctypes.c_uint), ("angles", ctypes.c_uint),
                    ("states", ctypes.POINTER(ctypes.c_char_p)),
                    ("units", ctypes.POINTER(ctypes.c_char_p))]

    class Export(ctypes.Structure):
        _fields_ = [("version", ctypes.c_uint), ("real_size", ctypes.c_uint),
                    ("model", ctypes.POINTER(Model))]
    try:
        ex = Export.in_dll(ctypes.CDLL(os.path.abspath(path)),
                           "gf_codegen_exported")
    except (OSError, ValueError):
        return [], []
    if ex.version != 1 or not ex.model or ex.model.contents.version != 1:
        return [], []
    d = ex.model.contents
    return ([d.states[i].decode() for i in range(d.n)],
            [d.units[i].decode() for i in range(d.n)])


def state_labels(config, track, model, n):
    """'name (unit)' of each of the n states of a track of this model
    (measurement_t.MODEL_*): the configured model whose channels name the
    track, as the node picks it; else the presets' names, else x0.."""
    names, units = PRESET.get(model, ([], []))
    for _, keys in read_config(config) if config else []:
        ch = keys.get("channels")
        if KINDS.get(keys.get("type")) != model or not ch or not any(
                re.fullmatch(ch, "GF_%s_%d" % (k, track))
                for k in ("MEAS", "CTRL")):
            continue
        if keys.get("type") == "generated" and "library" in keys:
            # named by its library (relative to the configuration's folder)
            names, units = library_states(os.path.join(
                os.path.dirname(os.path.abspath(config)), keys["library"]))
            break
        if "states" in keys or "motion" in keys:
            names = keys["states"].split() if "states" in keys else \
                axis_states(keys["motion"])
            units = []
        units = keys["units"].split() if "units" in keys else units
        break
    if len(names) != n:
        names = ["x%d" % i for i in range(n)]
    if len(units) != n:
        units = [""] * n
    return ["%s (%s)" % (a, u) if u else a for a, u in zip(names, units)]


KIND = {1: "car", 2: "robot", 3: "linear"}
# node_results_t's fields, the refusals after applied and gated
REFUSALS = ["duplicate", "out_of_order", "malformed", "type_mismatch",
            "bad_field", "unknown_channel", "track_limit", "nonfinite",
            "filter_error", "stale_session", "no_summary", "no_model",
            "late", "too_old"]


def refused(results):
    """'bad_field 20, late 3' (the results that refused any), or 'none'."""
    r = ["%s %d" % (k, getattr(results, k)) for k in REFUSALS
         if getattr(results, k)]
    return ", ".join(r) if r else "none"


def status_lines(s, track=None):
    """A node_status_t as text: the node's line, then a line per track."""
    lines = ["status %s seq %d%s (pid %d on %s): received %d, applied %d, "
             "gated %d, refused %s; gaps %d, dropped %d, kernel_drops %s, "
             "lost_before_first %d, name_clashes %d; queue %d (peak %d); "
             "%d tracks" % (
                 s.node, s.seq, " STOPPING" if s.stopping else "", s.pid,
                 s.host, s.received, s.results.applied, s.results.gated,
                 refused(s.results), s.gaps, s.dropped,
                 s.kernel_drops if s.kernel_drops >= 0 else "-",
                 s.lost_before_first, s.name_clashes, s.queue_depth,
                 s.queue_peak, s.ntracks)]
    for t in s.tracks:
        if track is not None and t.track != track:
            continue
        nis = "NIS last %.3f (m=%d), " % (t.nis_last, t.m_last) + (
            "mean %.3f over %d updates since the last status (%.3f per dof)"
            % (t.nis_mean, t.nis_updates, t.nis_per_dof) if t.nis_updates
            else "no update since the last status") if t.m_last else \
            "no update yet"
        lines.append("  track %d (%s, %s): inputs %d, applied %d, gated %d "
                     "(%d in a row), refused %s; %s; last input seq %d, "
                     "%s" % (
                         t.track, KIND.get(t.model, t.model), t.model_name,
                         t.inputs, t.results.applied, t.results.gated,
                         t.gated_run, refused(t.results), nis, t.input_seq,
                         "%.3f s ago" % t.age if t.age >= 0 else "age -"))
    return lines


def watch_status(a):
    """--status: prints every node_status_t until --count, --seconds
    without one, or the end of a log."""
    from gaussfilt_lcm import node_status_t
    lc = lcm.LCM(a.url) if a.url else lcm.LCM()
    seen = []

    def on_status(channel, data):
        s = node_status_t.decode(data)
        print("\n".join(status_lines(s, a.track)), flush=True)
        seen.append(s)

    lc.subscribe("GF_NODE_STATUS", on_status).set_queue_capacity(1000)
    print("beliefs.py: ready url=%s channel=GF_NODE_STATUS" % (
        a.url or "(LCM's default)"), flush=True)
    replay = bool(a.url) and a.url.startswith("file://")
    try:
        while not a.count or len(seen) < a.count:
            if replay:
                lc.handle()  # IOError at the end of the log
                continue
            r, _, _ = select.select([lc.fileno()], [], [],
                                    a.seconds if a.seconds > 0 else None)
            if not r:
                break
            lc.handle()
    except (KeyboardInterrupt, IOError):
        pass
    print("%d statuses from %d nodes" % (len(seen),
                                         len({s.node for s in seen})),
          flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--url", default=None, help="LCM URL (default: LCM's)")
    ap.add_argument("--track", type=int, default=None,
                    help="only this track (and the one --plot draws)")
    ap.add_argument("--plot", default=None, help="draw --track to this PNG")
    ap.add_argument("--config", default=None,
                    help="the node's configuration: the states' names")
    ap.add_argument("--count", type=int, default=0, help="stop after N beliefs")
    ap.add_argument("--seconds", type=float, default=0.0,
                    help="stop after S seconds without a belief")
    ap.add_argument("--status", action="store_true",
                    help="print the nodes' status messages instead")
    a = ap.parse_args()
    if a.status:
        if a.plot:
            ap.error("--status draws nothing")
        return watch_status(a)
    if a.plot and a.track is None:
        ap.error("--plot needs --track")

    lc = lcm.LCM(a.url) if a.url else lcm.LCM()
    seen, truths = [], []
    chan = "GF_BELIEF_%d" % a.track if a.track is not None else "GF_BELIEF_-?[0-9]+"

    def on_belief(channel, data):
        b = belief_t.decode(data)
        n = b.n
        mean = " ".join("%10.4f" % b.mean[i] for i in range(n))
        sd = " ".join("%9.4f" % math.sqrt(max(b.cov[i][i], 0.0))
                      if b.cov[i][i] == b.cov[i][i] else "      nan"
                      for i in range(n))
        nis = "%8.3f" % b.nis if b.m else "       -"
        print("%6d %6d %-7s %4d | %s | %s | %s" % (
            b.track, b.seq, STAGES.get(b.stage, b.stage), b.status, mean, sd,
            nis), flush=True)
        seen.append(b)

    # LCM keeps 30 messages per subscription by default: too few for a
    # node's bursts (a replayed log comes as fast as it was written)
    lc.subscribe(chan, on_belief).set_queue_capacity(100000)
    if a.plot:
        from gaussfilt_lcm import groundtruth_t

        def on_truth(channel, data):
            truths.append(groundtruth_t.decode(data))
        lc.subscribe(TRUTH + str(a.track), on_truth).set_queue_capacity(100000)
    print("beliefs.py: ready url=%s channel=%s" % (a.url or "(LCM's default)",
                                                    chan), flush=True)
    print("%6s %6s %-7s %4s | %s | %s | %s" % (
        "track", "seq", "stage", "st", "mean", "sd", "NIS"), flush=True)
    replay = bool(a.url) and a.url.startswith("file://")
    try:
        while not a.count or len(seen) < a.count:
            if replay:
                lc.handle()  # IOError at the end of the log
                continue
            r, _, _ = select.select([lc.fileno()], [], [],
                                    a.seconds if a.seconds > 0 else None)
            if not r:
                break
            lc.handle()
    except (KeyboardInterrupt, IOError):
        pass
    # belief seqs never seen, per track: from 0 (the initial belief) to the
    # last one seen
    missed = {}
    for t in sorted({b.track for b in seen}):
        seqs = {b.seq for b in seen if b.track == t}
        gone = max(seqs) + 1 - len(seqs)
        if gone:
            missed[t] = gone
    print("%d beliefs%s" % (len(seen), "; missed (never seen): " + ", ".join(
        "track %d: %d" % kv for kv in missed.items()) if missed else ""),
        flush=True)

    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        bs = [b for b in seen if b.track == a.track]
        if not bs:
            sys.exit("no beliefs of track %d to plot" % a.track)
        n = bs[0].n
        names = state_labels(a.config, a.track, bs[0].model, n)
        fig, axes = plt.subplots(n, 1, sharex=True, figsize=(7, 2.0 * n),
                                 squeeze=False)
        t = [b.utime * 1e-6 for b in bs]
        gt = sorted(truths, key=lambda g: g.seq)
        for i, ax in enumerate(axes[:, 0]):
            mu = [b.mean[i] for b in bs]
            sd = [math.sqrt(max(b.cov[i][i], 0.0)) for b in bs]
            ax.fill_between(t, [m - 2 * s for m, s in zip(mu, sd)],
                            [m + 2 * s for m, s in zip(mu, sd)], alpha=0.3,
                            step="post", label="2 sigma")
            ax.step(t, mu, where="post", lw=1, label="mean")
            if gt:
                ax.plot([g.utime * 1e-6 for g in gt],
                        [g.state[i] for g in gt], "k.", ms=2,
                        label="truth (groundtruth_t)")
            ax.set_ylabel(names[i])
        axes[0, 0].set_title("gf_node beliefs of track %d" % a.track)
        axes[0, 0].legend(loc="best", fontsize=8)
        axes[-1, 0].set_xlabel("time (s, the inputs' utime)")
        fig.tight_layout()
        fig.savefig(a.plot, dpi=100)
        print("drew %s (%d beliefs%s): %s" % (
            a.plot, len(bs), ", %d truths" % len(gt) if gt else "",
            ", ".join(names)))


if __name__ == "__main__":
    main()
