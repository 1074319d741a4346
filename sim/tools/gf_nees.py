# SPDX-License-Identifier: MIT
"""NEES and NIS of a node's beliefs against the simulator's truth, from LCM
logs, with their 95% bounds; and a figure of them over time.

    python gf_nees.py LOG [LOG...] [--track N | --tracks A-B] [--plot PNG]
                                          (scripts/nees LOG... [options])

Reads every belief (GF_BELIEF_<track>) and truth (GF_TRUTH_<track>) of the
logs (one log, or the simulator's and the node's apart), any model: car,
robot, a linear model of any n, the book's presets as well as configured
ones. Each corrected belief (STAGE_UPDATE, status 0) is paired with the
truth of its step (the last truth before its input: gf_sim sends a step's
control, its truth, then its measurement) and gives

    NEES = (x - mu)^T Sigma^-1 (x - mu)   (the robot's heading error wrapped)
    NIS  = y^T S^-1 y                     (belief_t.nis)

A belief whose covariance is not positive definite (e.g. the book-car
preset's first beliefs, from a prior known exactly) has no NEES: it is left
out of the NEES and counted ("k without NEES"). For a consistent filter
the means are n and m (chi-square). Printed per
track, then per model (tracks of one (model, n, m): the Monte-Carlo runs of
`gf_sim --runs`), each mean with the two-sided 95% interval of a mean of N
chi-square samples, chi2inv(0.025 / 0.975, N k) / N (Wilson-Hilferty's
approximation of the quantile). For the NIS, N is the number of updates:
innovations are white. For the NEES, N is the number of tracks: one
track's errors persist from step to step, so its samples are not
independent, and only runs are (as gf_consist's overall NEES bound; its
per-step test is sim/tests/gf_consist.c). --plot draws, per model, the
NEES and NIS of each step averaged over its tracks against time, with the
per-step 95% interval of that average.
"""
import argparse
import math
import sys
from collections import defaultdict

import lcm
from gaussfilt_lcm import belief_t, groundtruth_t

BELIEF, TRUTH = "GF_BELIEF_", "GF_TRUTH_"  # sim/gf_channels.h
STAGE_UPDATE = 2  # belief_t.STAGE_UPDATE
KINDS = {1: "car", 2: "robot", 3: "linear"}  # measurement_t.MODEL_*
Z975 = 1.959963984540054


def chi2_inv(p_z, k):
    """The chi-square quantile of k dof at the normal quantile p_z
    (Wilson-Hilferty)."""
    c = 2.0 / (9.0 * k)
    return k * (1.0 - c + p_z * math.sqrt(c)) ** 3


def bounds(k, n):
    """95% interval of the mean of n chi-square(k) samples."""
    return chi2_inv(-Z975, n * k) / n, chi2_inv(Z975, n * k) / n


def quad_form(cov, e):
    """e^T cov^-1 e by Cholesky; NaN if cov is not positive definite."""
    n = len(e)
    lo = [[0.0] * n for _ in range(n)]
    for j in range(n):
        d = cov[j][j] - sum(lo[j][k] ** 2 for k in range(j))
        if not d > 0.0:
            return float("nan")
        lo[j][j] = math.sqrt(d)
        for i in range(j + 1, n):
            lo[i][j] = (cov[i][j] - sum(lo[i][k] * lo[j][k]
                                        for k in range(j))) / lo[j][j]
    q, y = 0.0, [0.0] * n
    for i in range(n):
        y[i] = (e[i] - sum(lo[i][k] * y[k] for k in range(i))) / lo[i][i]
        q += y[i] * y[i]
    return q


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def read(paths, keep):
    beliefs, truths = defaultdict(list), defaultdict(list)
    for path in paths:
        for ev in lcm.EventLog(path, "r"):
            ch = ev.channel
            try:
                if ch.startswith(BELIEF) and keep(int(ch[len(BELIEF):])):
                    b = belief_t.decode(ev.data)
                    if b.stage == STAGE_UPDATE and b.status == 0 and b.m:
                        beliefs[b.track].append(b)
                elif ch.startswith(TRUTH) and keep(int(ch[len(TRUTH):])):
                    g = groundtruth_t.decode(ev.data)
                    truths[g.track].append(g)
            except ValueError:
                pass  # another type or another layout: not ours to judge
    return beliefs, truths


def samples(bs, gs):
    """[(utime, NEES, NIS, n, m)] of one track, by input seq."""
    gs = sorted(gs, key=lambda g: g.seq)
    seqs = [g.seq for g in gs]
    out, k = [], 0
    for b in sorted(bs, key=lambda b: b.input_seq):
        while k < len(seqs) and seqs[k] < b.input_seq:
            k += 1
        if k == 0:
            continue  # no truth before it
        g = gs[k - 1]
        if g.n != b.n:
            continue
        e = [g.state[i] - b.mean[i] for i in range(b.n)]
        if b.model == 2:
            e[2] = wrap(e[2])
        out.append((b.utime, quad_form(b.cov, e), b.nis, b.n, b.m, b.model))
    return out


def line(label, xs, k, n):
    """The mean of xs (NaN left out, and counted), judged as a mean of n
    independent chi-square(k)."""
    good = [x for x in xs if x == x]
    if not good:
        return "%s: none (%d without)" % (label, len(xs))
    mean = sum(good) / len(good)
    lo, hi = bounds(k, n)
    inside = "inside" if lo <= mean <= hi else "OUTSIDE"
    without = ", %d without %s" % (len(xs) - len(good), label) \
        if len(good) < len(xs) else ""
    return "%s %.3f (95%% bounds %.3f..%.3f, %s%s)" % (label, mean, lo, hi,
                                                         inside, without)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("logs", nargs="+", help="LCM logs (beliefs and truths)")
    ap.add_argument("--track", type=int, help="only this track")
    ap.add_argument("--tracks", help="only tracks A-B (inclusive)")
    ap.add_argument("--plot", help="draw NEES and NIS over time to this PNG")
    a = ap.parse_args()
    lo_t, hi_t = -2 ** 31, 2 ** 31
    if a.track is not None:
        lo_t = hi_t = a.track
    elif a.tracks:
        lo_t, hi_t = (int(x) for x in a.tracks.split("-", 1))
    beliefs, truths = read(a.logs, lambda t: lo_t <= t <= hi_t)
    groups = defaultdict(list)  # (model, n, m) -> [samples of a track]
    for t in sorted(beliefs):
        s = samples(beliefs[t], truths.get(t, []))
        if not s:
            continue
        n, m, model = s[0][3], s[0][4], s[0][5]
        groups[(model, n, m)].append((t, s))
        print("track %d (%s, n=%d, m=%d): %d updates: %s; %s" % (
            t, KINDS.get(model, model), n, m, len(s),
            line("NEES", [x[1] for x in s], n, 1),
            line("NIS", [x[2] for x in s], m, len(s))))
    if not groups:
        sys.exit("gf_nees: no corrected belief with a truth before it in %s"
                 % " ".join(a.logs))
    for (model, n, m), runs in sorted(groups.items()):
        nees = [x[1] for _, s in runs for x in s]
        nis = [x[2] for _, s in runs for x in s]
        print("all %d %s tracks (n=%d, m=%d): %d updates: %s; %s" % (
            len(runs), KINDS.get(model, model), n, m, len(nees),
            line("NEES", nees, n, len(runs)), line("NIS", nis, m, len(nis))))
    if a.plot:
        plot(groups, a.plot)


def plot(groups, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(groups), 2, figsize=(10, 3 * len(groups)),
                             squeeze=False)
    for row, ((model, n, m), runs) in enumerate(sorted(groups.items())):
        steps = min(len(s) for _, s in runs)
        t = [runs[0][1][i][0] * 1e-6 for i in range(steps)]
        for col, (what, k, idx) in enumerate((("NEES", n, 1), ("NIS", m, 2))):
            avg = []
            for i in range(steps):
                xs = [s[i][idx] for _, s in runs if s[i][idx] == s[i][idx]]
                avg.append(sum(xs) / len(xs) if xs else float("nan"))
            lo, hi = bounds(k, len(runs))
            ax = axes[row][col]
            ax.plot(t, avg, lw=1, label="%s, mean of %d track%s" % (
                what, len(runs), "s" if len(runs) > 1 else ""))
            ax.axhline(k, color="k", lw=0.8, label="expected: %d" % k)
            ax.axhspan(lo, hi, alpha=0.2, color="g", label="95% bounds")
            ax.set_title("%s n=%d m=%d: %s" % (KINDS.get(model, model), n, m,
                                               what))
            ax.set_xlabel("time (s)")
            ax.legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    print("drew %s" % path)


if __name__ == "__main__":
    main()
