# SPDX-License-Identifier: MIT
"""NEES and NIS of a node's beliefs against the simulator's truth, from LCM
logs, with their 95% bounds; the updates that are missing or were gated;
and a figure of them over time.

    python gf_nees.py LOG [LOG...] [--track N | --tracks A-B]
                      [--max-missing PERCENT] [--plot PNG] [--csv FILE]
                                          (scripts/nees LOG... [options])

Reads every belief (GF_BELIEF_<track>), truth (GF_TRUTH_<track>) and
measurement (GF_MEAS_<track>) of the logs (one log, or the simulator's and
the node's apart), any model: car, robot, a linear model of any n, the
book's presets as well as configured ones. Each update (a belief of
STAGE_UPDATE) that ran (status 0) or that the model's gate refused (status
-5, GF_ERR_GATED: its belief is the prediction, its NIS the one the gate
judged) is paired with the truth of its step (the last truth before its
input: gf_sim sends a step's control, its truth, then its measurement) and
gives

    NEES = (x - mu)^T Sigma^-1 (x - mu)   (the robot's heading error wrapped)
    NIS  = y^T S^-1 y                     (belief_t.nis)

Gated updates count in both means, and are said apart ("g gated"): left
out, a filter whose noise is too small would have its largest NIS dropped
and its NIS mean pulled down. An update the core refused for another
reason (a non-finite or singular input) has no NIS and is counted as
refused. A belief whose covariance is not positive definite (e.g. the
book-car preset's first beliefs, from a prior known exactly) has no NEES:
it is left out of the NEES and counted ("k without NEES").

A model's named sensors (GF_MEAS_<track>_<sensor>, docs/node.md) are
judged apart, a line per sensor: each sensor's update (belief_t.sensor,
its own seq) is paired with the truth at its utime (gf_sim sends the truth
at each sample's time) and its measurements counted on its channel.
Beliefs of gf_node --rate (belief_t.trigger) are no updates.

Missing updates: every measurement of a track in the logs (GF_MEAS_<track>,
e.g. gf_sim's own log of what it sent) should have an update belief (its
input_seq). Those with none are missing: lost on the way, or never
handled. A model's group, or all the logs together, with more than
--max-missing percent (default 1) of its measurements missing is NOT
JUDGED: its means are printed, but the tool says it cannot call it
consistent and exits 1. Without measurements in the logs the missing
updates cannot be counted: the lines say so.

For a consistent filter the means are n and m (chi-square). Printed per
track, then per model (tracks of one (model, n, m): the Monte-Carlo runs of
`gf_sim --runs`), each mean with the two-sided 95% interval of a mean of N
chi-square samples, chi2inv(0.025 / 0.975, N k) / N (Wilson-Hilferty's
approximation of the quantile). For the NIS, N is the number of updates:
innovations are white. For the NEES, N is the number of tracks: one
track's errors persist from step to step, so its samples are not
independent, and only runs are (as gf_consist's overall NEES bound; its
per-step test is sim/tests/gf_consist.c).

--plot draws, per model, the NEES and NIS averaged over the tracks that
have an update at each time (the beliefs' utime, aligned across runs by
time, not by update count: a run with a lost or gated update still lines
up with the others), with the 95% interval of that average for the number
of tracks averaged there; gated updates are marked. --csv writes those
averages, a row per model and time: time_s, tracks (averaged there), nees,
nees_lo, nees_hi, nis, nis_lo, nis_hi, gated (among them), model, n, m.

Exit status: 0 when every model's means lie inside their bounds and no
updates are missing beyond --max-missing; 1 when a mean lies OUTSIDE or a
group is NOT JUDGED; 2 for bad arguments or logs with nothing to judge.
"""
import argparse
import bisect
import math
import sys
from collections import defaultdict

import lcm
from gaussfilt_lcm import belief_t, groundtruth_t, measurement_t

BELIEF, TRUTH, MEAS = "GF_BELIEF_", "GF_TRUTH_", "GF_MEAS_"  # gf_channels.h
STAGE_UPDATE = 2  # belief_t.STAGE_UPDATE
GATED = -5  # GF_ERR_GATED
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


class Track:
    def __init__(self):
        self.updates = {}   # (sensor, input_seq) -> belief_t of STAGE_UPDATE
        self.truths = []    # groundtruth_t
        self.meas = set()   # (sensor, seq) of the measurements in the logs
        self.meas_model = None


def meas_channel(ch):
    """GF_MEAS_<track> or GF_MEAS_<track>_<sensor>: (track, sensor)."""
    track, _, sensor = ch[len(MEAS):].partition("_")
    return int(track), sensor


def read(paths, keep):
    tracks = defaultdict(Track)
    for path in paths:
        for ev in lcm.EventLog(path, "r"):
            ch = ev.channel
            try:
                if ch.startswith(BELIEF) and keep(int(ch[len(BELIEF):])):
                    b = belief_t.decode(ev.data)
                    if b.stage == STAGE_UPDATE and not b.trigger:
                        tracks[b.track].updates[(b.sensor, b.input_seq)] = b
                elif ch.startswith(TRUTH) and keep(int(ch[len(TRUTH):])):
                    tracks[int(ch[len(TRUTH):])].truths.append(
                        groundtruth_t.decode(ev.data))
                elif ch.startswith(MEAS) and keep(meas_channel(ch)[0]):
                    z = measurement_t.decode(ev.data)
                    t = tracks[z.track]
                    t.meas.add((meas_channel(ch)[1], z.seq))
                    t.meas_model = z.model
            except ValueError:
                pass  # another type or another layout: not ours to judge
    return tracks


class Result:
    """One track's samples and counts (of one of its sensors)."""

    def __init__(self, track, sensor=""):
        self.track = track
        self.sensor = sensor
        self.samples = []  # (utime, NEES, NIS, gated)
        self.gated = self.refused = 0
        self.expected = None  # measurements in the logs, None: unknown
        self.missing = 0
        self.key = None  # (model, n, m, sensor)


def judge_track(t, tr):
    """A Result per sensor of the track ("": GF_MEAS_<track>)."""
    sensors = sorted({k[0] for k in tr.updates} | {k[0] for k in tr.meas})
    return [judge_sensor(t, tr, sensor) for sensor in sensors or [""]]


def judge_sensor(t, tr, sensor):
    r = Result(t, sensor)
    gs = sorted(tr.truths, key=lambda g: g.seq)
    seqs = [g.seq for g in gs]
    by_time = sorted(tr.truths, key=lambda g: g.utime)
    utimes = [g.utime for g in by_time]
    updates = {k[1]: b for k, b in tr.updates.items() if k[0] == sensor}
    if tr.meas:
        meas = {k[1] for k in tr.meas if k[0] == sensor}
        r.expected = len(meas)
        r.missing = len(meas - set(updates))
    for s in sorted(updates):
        b = updates[s]
        if b.status not in (0, GATED) or not b.m:
            r.refused += 1
            continue
        r.key = (b.model, b.n, b.m, sensor)
        if sensor:
            # a sensor's sample: the truth at its time (gf_sim sends the
            # truth at each sample's utime, before the measurement)
            k = bisect.bisect_right(utimes, b.utime)
            gs_k = by_time
        else:
            # the last truth before the input (by seq)
            k = bisect.bisect_left(seqs, s)
            gs_k = gs
        if k == 0:
            continue  # no truth before it: not a sample
        nees = float("nan")
        if gs_k[k - 1].n == b.n:
            g = gs_k[k - 1]
            e = [g.state[i] - b.mean[i] for i in range(b.n)]
            if b.model == 2:
                e[2] = wrap(e[2])
            nees = quad_form(b.cov, e)
        gated = b.status == GATED
        r.gated += gated
        r.samples.append((b.utime, nees, b.nis, gated))
    if r.key is None and tr.meas:
        r.key = (tr.meas_model, 0, 0, sensor)  # no update: all missing
    return r


def label(model, n, m, sensor):
    return "%s, n=%d, m=%d%s" % (KINDS.get(model, model), n, m,
                                 ", sensor " + sensor if sensor else "")


def line(label, xs, k, n):
    """The mean of xs (NaN left out, and counted), judged as a mean of n
    independent chi-square(k). Returns (text, inside or None)."""
    good = [x for x in xs if x == x]
    if not good or k == 0:
        return "%s: none (%d without)" % (label, len(xs)), None
    mean = sum(good) / len(good)
    lo, hi = bounds(k, n)
    inside = lo <= mean <= hi
    without = ", %d without %s" % (len(xs) - len(good), label) \
        if len(good) < len(xs) else ""
    return "%s %.3f (95%% bounds %.3f..%.3f, %s%s)" % (
        label, mean, lo, hi, "inside" if inside else "OUTSIDE", without), \
        inside


def counts(n_updates, gated, refused, expected, missing):
    s = "%d updates (%d gated" % (n_updates, gated)
    if refused:
        s += ", %d refused" % refused
    if expected is None:
        s += ", missing unknown: no measurements in the logs)"
    else:
        s += ", %d missing of %d measurements)" % (missing, expected)
    return s


def over(missing, expected, limit):
    return expected and 100.0 * missing / expected > limit


def main():
    ap = argparse.ArgumentParser(
        description=__doc__.splitlines()[0],
        epilog="See the top of sim/tools/gf_nees.py for how each number "
               "is judged.")
    ap.add_argument("logs", nargs="+", help="LCM logs (beliefs and truths)")
    ap.add_argument("--track", type=int, help="only this track")
    ap.add_argument("--tracks", help="only tracks A-B (inclusive)")
    ap.add_argument("--max-missing", type=float, default=1.0,
                    metavar="PERCENT",
                    help="missing updates a group may have and still be "
                         "judged (default 1)")
    ap.add_argument("--plot", help="draw NEES and NIS over time to this PNG")
    ap.add_argument("--csv", help="write the per-time averages to this file")
    a = ap.parse_args()
    lo_t, hi_t = -2 ** 31, 2 ** 31
    if a.track is not None:
        lo_t = hi_t = a.track
    elif a.tracks:
        try:
            lo_t, hi_t = (int(x) for x in a.tracks.split("-", 1))
        except ValueError:
            ap.error("--tracks A-B, e.g. 400-449")
    tracks = read(a.logs, lambda t: lo_t <= t <= hi_t)
    groups = defaultdict(list)  # (model, n, m, sensor) -> [Result]
    no_truth = []
    for t in sorted(tracks):
        if not tracks[t].truths:
            if tracks[t].updates:
                no_truth.append(t)
            continue
        for r in judge_track(t, tracks[t]):
            if r.key is None:
                continue  # truths only, or refused updates only
            groups[r.key].append(r)
            model, n, m, sensor = r.key
            if n == 0:
                print("track %d (%s%s): %s: no update belief of it in the "
                      "logs" % (t, KINDS.get(model, model),
                                ", sensor " + sensor if sensor else "",
                                counts(0, 0, r.refused, r.expected,
                                       r.missing)))
                continue
            nees, _ = line("NEES", [x[1] for x in r.samples], n, 1)
            nis, _ = line("NIS", [x[2] for x in r.samples], m,
                          len(r.samples))
            print("track %d (%s): %s: %s; %s" % (
                t, label(model, n, m, sensor),
                counts(len(r.samples), r.gated, r.refused, r.expected,
                       r.missing), nees, nis))
    if no_truth:
        print("left out, no truth in the logs: track%s %s" % (
            "s" if len(no_truth) > 1 else "",
            ", ".join(str(t) for t in no_truth)))
    if not groups:
        print("gf_nees: no update belief with a truth before it in %s "
              "(the truths are in gf_sim's log, the beliefs in the node's: "
              "give both)" % " ".join(a.logs), file=sys.stderr)
        sys.exit(2)
    verdict = 0
    all_expected = all_missing = 0
    unknown = False
    for (model, n, m, sensor), runs in sorted(groups.items(),
                                              key=lambda kv: tuple(kv[0])):
        samples = [x for r in runs for x in r.samples]
        gated = sum(r.gated for r in runs)
        refused = sum(r.refused for r in runs)
        if any(r.expected is None for r in runs):
            expected, unknown = None, True
        else:
            expected = sum(r.expected for r in runs)
            all_expected += expected
        missing = sum(r.missing for r in runs)
        all_missing += missing
        head = "all %d %s tracks (n=%d, m=%d%s): %s" % (
            len(runs), KINDS.get(model, model), n, m,
            ", sensor " + sensor if sensor else "",
            counts(len(samples), gated, refused, expected, missing))
        if n == 0:
            print("all %d %s tracks without beliefs: %s: no update belief "
                  "in the logs (the node's log too?)" % (
                      len(runs), KINDS.get(model, model),
                      counts(0, 0, refused, expected, missing)))
            verdict = 1
            continue
        nees, nees_in = line("NEES", [x[1] for x in samples], n, len(runs))
        nis, nis_in = line("NIS", [x[2] for x in samples], m, len(samples))
        print("%s: %s; %s" % (head, nees, nis))
        if expected is not None and over(missing, expected, a.max_missing):
            print("NOT JUDGED: %s tracks (%s): %d of %d updates "
                  "missing (%.1f%% > %g%%): their means cannot say the "
                  "filter is consistent" % (
                      KINDS.get(model, model),
                      label(model, n, m, sensor).split(", ", 1)[1],
                      missing, expected,
                      100.0 * missing / expected, a.max_missing))
            verdict = 1
        elif nees_in is False or nis_in is False:
            verdict = 1
    if all_expected and over(all_missing, all_expected, a.max_missing):
        print("NOT JUDGED: %d of %d updates missing in all (%.1f%% > %g%%)"
              % (all_missing, all_expected,
                 100.0 * all_missing / all_expected, a.max_missing))
        verdict = 1
    elif unknown:
        print("missing updates not counted: the logs hold no measurements "
              "of some tracks (add gf_sim's own log)")
    if a.csv:
        write_csv(groups, a.csv)
    if a.plot:
        plot(groups, a.plot)
    sys.exit(verdict)


def series(runs, n, m):
    """The per-time averages of one model's tracks, aligned by utime:
    [(utime, tracks, (NEES mean, lo, hi), (NIS mean, lo, hi), gated)],
    the bounds those of a mean over the tracks that have an update then."""
    by_time = defaultdict(list)  # utime -> [(NEES, NIS, gated)]
    for r in runs:
        for ut, nees, nis, gated in r.samples:
            by_time[ut].append((nees, nis, gated))
    out = []
    for ut in sorted(by_time):
        row = [ut, len(by_time[ut])]
        for idx, k in ((0, n), (1, m)):
            xs = [x[idx] for x in by_time[ut] if x[idx] == x[idx]]
            if xs:
                row.append((sum(xs) / len(xs),) + bounds(k, len(xs)))
            else:
                row.append((float("nan"),) * 3)
        row.append(sum(x[2] for x in by_time[ut]))
        out.append(tuple(row))
    return out


def write_csv(groups, path):
    with open(path, "w") as f:
        f.write("time_s,tracks,nees,nees_lo,nees_hi,nis,nis_lo,nis_hi,"
                "gated,model,n,m\n")
        for (model, n, m, sensor), runs in sorted(groups.items()):
            if n == 0:
                continue
            for ut, k, nees, nis, gated in series(runs, n, m):
                f.write("%.6f,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%d,%s,%d,%d\n"
                        % ((ut * 1e-6, k) + nees + nis +
                           (gated, KINDS.get(model, model) +
                            ("/" + sensor if sensor else ""), n, m)))
    print("wrote %s" % path)


def plot(groups, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    groups = {k: v for k, v in groups.items() if k[1] > 0}
    fig, axes = plt.subplots(len(groups), 2, figsize=(10, 3 * len(groups)),
                             squeeze=False)
    for row, ((model, n, m, sensor), runs) in enumerate(
            sorted(groups.items())):
        rows = series(runs, n, m)
        t = [x[0] * 1e-6 for x in rows]
        for col, (what, k, idx) in enumerate((("NEES", n, 2), ("NIS", m, 3))):
            avg = [x[idx][0] for x in rows]
            ax = axes[row][col]
            ax.fill_between(t, [x[idx][1] for x in rows],
                            [x[idx][2] for x in rows], step="mid", alpha=0.2,
                            color="g",
                            label="95% bounds (of the tracks averaged)")
            ax.plot(t, avg, lw=1, label="%s, mean over the %d track%s at "
                    "each time" % (what, len(runs),
                                   "s" if len(runs) > 1 else ""))
            gated = [(ti, v) for ti, v, x in zip(t, avg, rows) if x[4]]
            if gated:
                ax.plot([g[0] for g in gated], [g[1] for g in gated], "rx",
                        ms=4, label="a gated update among them")
            ax.axhline(k, color="k", lw=0.8, label="expected: %d" % k)
            ax.set_title("%s: %s" % (label(model, n, m, sensor), what))
            ax.set_xlabel("time (s, the beliefs' utime)")
            ax.legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    print("drew %s" % path)


if __name__ == "__main__":
    main()
