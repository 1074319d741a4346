# SPDX-License-Identifier: MIT
"""Draws tracks of any model from an LCM log: each state over time, the
mean, its 2-sigma band, and the simulator's truth when the log has it.

    python gf_track.py LOG [LOG...] --track N [--track M ...] [--config FILE]
                       [--out FILE.png | --dir DIR]
                                      (scripts/plot LOG --track N [...])

Reads the beliefs (GF_BELIEF_<track>) and truths (GF_TRUTH_<track>) of the
tracks asked for from the logs (one, or e.g. gf_sim's and a node's apart) with lcm.EventLog and the gaussfilt_lcm types; any model
(car, robot, linear of any n; configured or the book's presets). The x
axis is time in seconds, the beliefs' utime (the inputs' time: simulated
time for gf_sim's streams). The states are named as examples/beliefs.py
names them: from --config, the gf_node configuration of the track's model
(its states = and units = lines, or its motion = axes), else the presets'
names (car: position, velocity; robot: x, y, theta), else x0, x1, ...
Updates the model's gate refused (status -5) are marked with a red x on
the mean; a failed step (another negative status) with a black x.

Writes FILE.png (one track), or DIR/track_N.png per track (DIR default:
the current directory). Exits 2 naming what is missing when the log has
no beliefs of a track asked for.
"""
import argparse
import math
import os
import sys
from collections import defaultdict

import lcm
from gaussfilt_lcm import belief_t, groundtruth_t

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "examples"))
from beliefs import state_labels  # noqa: E402

BELIEF, TRUTH = "GF_BELIEF_", "GF_TRUTH_"  # sim/gf_channels.h
KINDS = {1: "car", 2: "robot", 3: "linear"}  # measurement_t.MODEL_*
FILTERS = {1: "KF2", 2: "EKF3", 3: "UKF3", 4: "PF3", 5: "KF"}  # FILTER_*
STAGE_UPDATE, GATED = 2, -5


def read(paths, tracks):
    beliefs, truths = defaultdict(list), defaultdict(list)
    for ev in (ev for p in paths for ev in lcm.EventLog(p, "r")):
        ch = ev.channel
        try:
            if ch.startswith(BELIEF) and int(ch[len(BELIEF):]) in tracks:
                b = belief_t.decode(ev.data)
                beliefs[b.track].append(b)
            elif ch.startswith(TRUTH) and int(ch[len(TRUTH):]) in tracks:
                truths[int(ch[len(TRUTH):])].append(
                    groundtruth_t.decode(ev.data))
        except ValueError:
            pass  # another type on the channel: not a belief to draw
    return beliefs, truths


def draw(track, bs, gs, labels, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bs = sorted(bs, key=lambda b: (b.utime, b.seq))
    gs = sorted(gs, key=lambda g: (g.utime, g.seq))
    n = bs[-1].n
    fig, axes = plt.subplots(n, 1, sharex=True, figsize=(8, 1.9 * n + 0.8),
                             squeeze=False)
    t = [b.utime * 1e-6 for b in bs]
    for i, ax in enumerate(axes[:, 0]):
        mu = [b.mean[i] if b.n == n else float("nan") for b in bs]
        sd = [math.sqrt(b.cov[i][i]) if b.n == n and b.cov[i][i] >= 0
              else float("nan") for b in bs]
        ax.fill_between(t, [m - 2 * s for m, s in zip(mu, sd)],
                        [m + 2 * s for m, s in zip(mu, sd)], alpha=0.3,
                        step="post", label="mean +- 2 sigma")
        ax.step(t, mu, where="post", lw=1, label="mean")
        if gs:
            ax.plot([g.utime * 1e-6 for g in gs],
                    [g.state[i] if g.n == n else float("nan") for g in gs],
                    "k.", ms=2, label="truth (groundtruth_t)")
        gated = [(tb, m) for tb, m, b in zip(t, mu, bs)
                 if b.stage == STAGE_UPDATE and b.status == GATED]
        failed = [(tb, m) for tb, m, b in zip(t, mu, bs)
                  if b.status < 0 and b.status != GATED]
        if gated:
            ax.plot(*zip(*gated), "rx", ms=5, label="gated update")
        if failed:
            ax.plot(*zip(*failed), "kx", ms=5, label="failed step")
        ax.set_ylabel(labels[i])
        ax.grid(alpha=0.3)
    b = bs[-1]
    axes[0, 0].set_title("track %d: %s, %s, n = %d (%d beliefs%s)" % (
        track, KINDS.get(b.model, b.model), FILTERS.get(b.filter, b.filter),
        n, len(bs), ", %d truths" % len(gs) if gs else ", no truth in the log"))
    axes[0, 0].legend(loc="best", fontsize=7)
    axes[-1, 0].set_xlabel("time (s, the beliefs' utime)")
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    plt.close(fig)
    print("drew %s (track %d: %d beliefs%s): %s" % (
        out, track, len(bs), ", %d truths" % len(gs) if gs else "",
        ", ".join(labels)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("logs", nargs="+", metavar="LOG")
    ap.add_argument("--track", type=int, action="append", required=True,
                    help="a track to draw (repeatable)")
    ap.add_argument("--config", help="the node's configuration: the states' "
                    "names and units")
    ap.add_argument("--out", help="the PNG (one track)")
    ap.add_argument("--dir", default=".", help="where track_N.png go")
    a = ap.parse_args()
    if a.out and len(a.track) > 1:
        ap.error("--out takes one track; --dir for several")
    beliefs, truths = read(a.logs, set(a.track))
    lacking = [t for t in a.track if not beliefs.get(t)]
    if lacking:
        print("gf_track: %s has no beliefs of track %s" % (
            " ".join(a.logs), ", ".join(str(t) for t in lacking)), file=sys.stderr)
        sys.exit(2)
    if not a.out:
        os.makedirs(a.dir, exist_ok=True)
    for t in a.track:
        b = beliefs[t][-1]
        out = a.out or os.path.join(a.dir, "track_%d.png" % t)
        draw(t, beliefs[t], truths.get(t, []),
             state_labels(a.config, t, b.model, b.n), out)


if __name__ == "__main__":
    main()
