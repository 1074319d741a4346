# SPDX-License-Identifier: MIT
"""Draws the worked solutions' figures from an LCM log recorded by scripts/demo, or
from the beliefs examples/exercises --beliefs wrote (scripts/demo --core).

    python gf_plots.py LOG OUT_DIR        (scripts/plot LOG [DIR])

Reads the beliefs (GF_BELIEF_<track>), the particle clouds
(GF_PARTICLES_<track>), the measurements (GF_MEAS_<track>) and the ground
truth (GF_TRUTH_<track>) with lcm.EventLog and the gaussfilt_lcm types (the
package scripts/lcm.sh installs into the venv), or the text file, and
writes PNGs (the figures of a changed exercise say its own numbers):

  fig1_1_ellipses.png     Figure 1.1: 68% ellipses of the car, t = 0..5 (track 1)
  fig1_2_correlation.png  Figure 1.2: rho_t, t = 1..10 (track 1)
  fig2_1_measurement.png  Figure 2.1: t = 0..5, then after z = 5 (track 2)
  fig4_1_prediction.png   Figure 4.1: the robot before and after moving (track 4)
  fig4_2_correction.png   Figure 4.2: ... and after seeing x = -0.7 (track 4)
  stream_car.png          the random car streamed in real time (track 10)
  ex4_three_ways.png      exercise 4 through three nodes: EKF (track 41), UKF
                          (42) and particle filter (43, beliefs and the
                          particle clouds of GF_PARTICLES_43)

Ellipses, marginals and correlations are computed from the covariances on
the wire by the library itself (gf_cov2_ellipse, gf_cov2_marginal and
gf_cov2_correlation through the Python package gaussfilt, float64;
docs/python.md), not by a second implementation here.
"""
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Ellipse  # noqa: E402

import gaussfilt  # noqa: E402
from gaussfilt import float64 as gf  # noqa: E402

# belief_t's stages (lcm_types/belief_t.lcm)
STAGE_INIT, STAGE_PREDICT, STAGE_UPDATE = 0, 1, 2
TEXT_MAGIC = "# gaussfilt beliefs"

# Channel prefixes: sim/gf_channels.h.
BELIEF, TRUTH, MEAS = "GF_BELIEF_", "GF_TRUTH_", "GF_MEAS_"
PARTICLES = "GF_PARTICLES_"
# scripts/demo's exercise-4 tracks, one node per filter (sim/tools/demo_live.sh)
EX4_TRACKS = {"EKF": 41, "UKF": 42, "PF": 43}
P = 0.68
K = math.sqrt(-2.0 * math.log(1.0 - P))


class Belief:
    """A belief read from text, with belief_t's fields the figures use."""

    def __init__(self, f):
        self.track, self.seq, self.stage, self.n = (int(x) for x in f[:4])
        v = [float(x) for x in f[4:16]]
        self.mean = v[0:3]
        self.cov = [v[3:6], v[6:9], v[9:12]]
        self.utime, self.filter, self.status = 0, 0, 0


def read_text(path, meas):
    """The text of examples/exercises --beliefs: one belief a line."""
    beliefs = defaultdict(dict)
    for line in open(path):
        f = line.split()
        if line.startswith("# meas"):
            meas[int(f[2])] = (float(f[3]), float(f[4]))
        elif f and not line.startswith("#"):
            b = Belief(f)
            beliefs[b.track][b.seq] = b
    return ({t: [d[s] for s in sorted(d)] for t, d in beliefs.items()},
            defaultdict(list))


def read(path, clouds=None, meas=None):
    """beliefs[track] = [belief_t by seq], truths[track] = [groundtruth_t];
    clouds[track][seq] = particles_t if a dict is given; meas[track] = (z,
    q) of the track's last scalar measurement if a dict is given."""
    meas = {} if meas is None else meas
    with open(path, "rb") as f:
        if f.read(len(TEXT_MAGIC)) == TEXT_MAGIC.encode():
            return read_text(path, meas)
    import lcm
    from gaussfilt_lcm import (belief_t, groundtruth_t, measurement_t,
                               particles_t)
    beliefs, truths = defaultdict(dict), defaultdict(list)
    for ev in lcm.EventLog(path, "r"):
        if ev.channel.startswith(MEAS):
            z = measurement_t.decode(ev.data)
            if z.m == 1:
                meas[z.track] = (z.z[0], z.q[0][0])
            continue
        if ev.channel.startswith(PARTICLES) and clouds is not None:
            c = particles_t.decode(ev.data)
            clouds.setdefault(c.track, {})[c.seq] = c
        elif ev.channel.startswith(BELIEF):
            b = belief_t.decode(ev.data)
            beliefs[b.track][b.seq] = b
        elif ev.channel.startswith(TRUTH):
            truths[int(ev.channel[len(TRUTH):])].append(
                groundtruth_t.decode(ev.data))
    return ({t: [d[s] for s in sorted(d)] for t, d in beliefs.items()},
            truths)


def marginal(b, i, j):
    """The 2x2 covariance of states i and j of belief b (gf_cov2_marginal
    for a 3-state belief)."""
    c = np.array(b.cov, dtype=float)
    if c.shape == (3, 3):
        return gf.marginal(c, i, j)
    return c[np.ix_([i, j], [i, j])]


def ellipse(ax, b, i=0, j=1, fill_alpha=0.0, **kw):
    """The 68% ellipse of the (i, j) marginal of belief b (gf_cov2_ellipse);
    a dot if it is degenerate in both axes. Returns its semi-axes (a >= b)."""
    a, bb, angle = gf.ellipse(marginal(b, i, j), P)
    angle = math.degrees(angle)
    centre = (b.mean[i], b.mean[j])
    colour = kw.pop("edgecolor", "k")
    label = kw.pop("label", None)
    if a == 0.0:
        ax.plot(*centre, "o", color=colour, label=label)
        return a, bb
    if fill_alpha > 0.0:
        ax.add_patch(Ellipse(centre, 2 * a, 2 * bb, angle=angle, lw=0,
                             facecolor=colour, alpha=fill_alpha))
    ax.add_patch(Ellipse(centre, 2 * a, 2 * bb, angle=angle, fill=False,
                         lw=1.8, edgecolor=colour, label=label, **kw))
    ax.plot(*centre, "+", color=colour)
    return a, bb


def rho(b):
    """The correlation of states 0 and 1 (gf_cov2_correlation); nan where
    it is undefined (t = 0: both variances zero)."""
    try:
        return gf.correlation(marginal(b, 0, 1))
    except gaussfilt.Undefined:
        return float("nan")


def car_ellipses(ax, bs, colours, lo=0.1, hi=0.85):
    for t, b in enumerate(bs):
        ellipse(ax, b, label=f"t = {t}",
                edgecolor=colours(lo + (hi - lo) * t / max(1, len(bs) - 1)))
    ax.set_xlabel("position x")
    ax.set_ylabel("velocity x'")
    ax.grid(alpha=0.3)


def fig_1_1(beliefs, out):
    bs = [b for b in beliefs[1] if b.seq <= 5]
    fig, ax = plt.subplots(figsize=(7, 5))
    car_ellipses(ax, bs, plt.cm.viridis)
    ax.set_xlim(-13, 13)
    ax.set_ylim(-4.5, 4.5)
    ax.set_title("Figure 1.1: the car's belief, t = 0..5 (68% ellipses, "
                 "from the wire)")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def fig_1_2(beliefs, out):
    bs = [b for b in beliefs[1] if 1 <= b.seq <= 10]
    fig, ax = plt.subplots(figsize=(7, 4))
    ts = [b.seq for b in bs]
    ax.plot(ts, [rho(b) for b in bs], "o-", label="rho_t (from the wire)")
    ax.axhline(math.sqrt(3) / 2, color="grey", ls="--",
               label="sqrt(3)/2 = 0.866 (limit)")
    ax.set_xlabel("t")
    ax.set_ylabel("correlation of position and velocity")
    ax.set_ylim(0.8, 1.01)
    ax.set_xticks(range(1, 11))
    ax.set_title("Figure 1.2: correlation coefficient (t = 0 undefined)")
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def fig_2_1(beliefs, out, meas):
    bs = beliefs[2]
    pred = [b for b in bs if b.stage != STAGE_UPDATE]
    upd = [b for b in bs if b.stage == STAGE_UPDATE]
    t = len(pred) - 1
    z, q = meas.get(2, (5.0, 10.0))
    fig, ax = plt.subplots(figsize=(7, 5))
    car_ellipses(ax, pred, plt.cm.Blues, 0.35, 0.95)
    for b in upd:
        ellipse(ax, b, edgecolor="green", label=f"t = {t} after z = {z:g}")
    ax.axvline(z, color="green", ls="--", label=f"z = {z:g} (variance {q:g})")
    wx = max([13.0, abs(z) + 2.0] +
             [1.1 * K * math.sqrt(max(b.cov[0][0], 0.0)) for b in bs])
    wv = max([4.5] + [1.1 * K * math.sqrt(max(b.cov[1][1], 0.0)) for b in bs])
    ax.set_xlim(-wx, wx)
    ax.set_ylim(-wv, wv)
    ax.set_title(f"Figure 2.1: the measurement z = {z:g} at t = {t} "
                 "(68% ellipses)")
    ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)


def fig_4(beliefs, out, corrected):
    """Left: the whole 68% ellipses (y reaches +-151 after the move);
    right: close up, equal axes, with the unit circle."""
    bs = beliefs[4][: 3 if corrected else 2]
    names = ["initial", "predicted", "corrected"]
    colours = ["tab:blue", "tab:purple", "tab:red"]
    fig, (full, near) = plt.subplots(1, 2, figsize=(12, 6),
                                     gridspec_kw={"width_ratios": [1, 1.6]})
    th = np.linspace(0, 2 * np.pi, 200)
    y_hit = math.sqrt(1 - 0.7 ** 2)
    for ax in (full, near):
        ax.plot(np.cos(th), np.sin(th), color="gold", lw=2.5,
                label="unit circle: where the robot can be")
        for b in bs:
            a, _ = ellipse(ax, b, fill_alpha=0.12, edgecolor=colours[b.seq],
                           label=f"{names[b.seq]}: mu = ({b.mean[0]:.2f}, "
                                 f"{b.mean[1]:.2f}), 68% ellipse")
        if corrected:
            ax.axvline(-0.7, color="green", ls="--", label="z = -0.7")
            ax.plot([-0.7, -0.7], [y_hit, -y_hit], "kx", ms=12, mew=2.5,
                    label=f"where it must be: (-0.7, +-{y_hit:.3f})")
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.grid(alpha=0.3)
    full.set_xlim(-1.6, 1.6)
    full.set_ylim(-200, 200)
    full.set_title("whole ellipses (y axis squeezed)")
    near.set_aspect("equal")
    near.set_xlim(-1.6, 1.6)
    near.set_ylim(-1.3, 1.3)
    near.set_title("close up, equal axes")
    handles, labels = near.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=9)
    fig.suptitle("Figure 4.2: the robot after seeing x = -0.7" if corrected
                 else "Figure 4.1: the robot before and after moving 1 "
                      "forward", fontsize=13)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(out)
    plt.close(fig)


def stream_car(beliefs, truths, out):
    bs = [b for b in beliefs.get(10, []) if b.stage == STAGE_UPDATE]
    ts = truths.get(10, [])
    if not bs or not ts:
        return False
    fig, ax = plt.subplots(figsize=(8, 4))
    step_us = bs[0].utime  # the first step ends at t = 1 step
    t_b = np.array([b.utime for b in bs]) / step_us
    x = np.array([b.mean[0] for b in bs])
    sd = np.sqrt([b.cov[0][0] for b in bs])
    ax.fill_between(t_b, x - 2 * sd, x + 2 * sd, alpha=0.25,
                    label="belief +- 2 sigma")
    ax.plot(t_b, x, label="belief mean (from the wire)")
    ax.plot(np.array([g.utime for g in ts]) / step_us,
            [g.state[0] for g in ts], "k--", lw=1, label="ground truth")
    ax.set_xlabel("step t")
    ax.set_ylabel("position")
    ax.set_title("The random car (exercise 1 noise, z every step, Q = 10), streamed at 50 Hz (track 10)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    return True


FILTER_NAMES = {1: "KF2", 2: "EKF3",  # belief_t.FILTER_*
                3: "UKF3", 4: "PF3"}


def ex4_three_ways(beliefs, clouds, out):
    """Exercise 4 through three nodes, from the wire: left after the move,
    right after z = -0.7. EKF and UKF as 68% ellipses; the particle filter
    as its cloud (GF_PARTICLES_43; dot area = weight, all equal once
    resampled) with its Gaussian summary (the belief it publishes) dashed."""
    tr = EX4_TRACKS
    if any(len(beliefs.get(t, [])) < 3 for t in tr.values()) or \
            len(clouds.get(tr["PF"], {})) < 3:
        return False
    colours = {"EKF": "tab:red", "UKF": "tab:blue", "PF": "tab:green"}
    th = np.linspace(0, 2 * np.pi, 300)
    y_hit = math.sqrt(1 - 0.7 ** 2)
    fig, axes = plt.subplots(1, 2, figsize=(14, 6.4))
    for ax, seq, title in ((axes[0], 1, "after moving 1 forward"),
                           (axes[1], 2, "after seeing x = -0.7")):
        ax.plot(np.cos(th), np.sin(th), color="gold", lw=2.5, zorder=1,
                label="unit circle: where the robot can be")
        c = clouds[tr["PF"]][seq]
        w = np.array(c.w, dtype=float)
        w = w / w.sum() if w.sum() > 0 else w
        size = 8.0 * w * len(w) if w.sum() > 0 else 8.0
        ax.scatter(c.x, c.y, s=size, color="tab:green", alpha=0.55,
                   lw=0, zorder=2,
                   label=f"PF particles ({c.count} of {c.n_filter} sent"
                         f"{', resampled' if c.resampled else ''}; "
                         f"neff {c.neff:.0f})")
        for name in ("EKF", "UKF", "PF"):
            b = beliefs[tr[name]][seq]
            kind = FILTER_NAMES.get(b.filter, "?")
            if name == "PF":
                ellipse(ax, b, edgecolor=colours[name], ls="--",
                        label=f"{kind} summary: mu = ({b.mean[0]:.2f}, "
                              f"{b.mean[1]:.2f}), where no particle is")
            else:
                ellipse(ax, b, fill_alpha=0.10, edgecolor=colours[name],
                        label=f"{kind}: mu = ({b.mean[0]:.2f}, "
                              f"{b.mean[1]:.2f}), 68% ellipse")
        if seq == 2:
            ax.axvline(-0.7, color="grey", ls=":", label="z = -0.7")
        ax.plot([-0.7, -0.7], [y_hit, -y_hit], "kx", ms=13, mew=2.5, zorder=5,
                label=f"where it must be: (-0.7, +-{y_hit:.3f})")
        ax.set_aspect("equal")
        ax.set_xlim(-1.7, 1.7)
        ax.set_ylim(-1.35, 1.35)
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.grid(alpha=0.3)
        ax.set_title(title)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2,
                  fontsize=8)
    fig.suptitle("Exercise 4 three ways, from the wire: EKF (track 41), UKF "
                 "(42), particle filter (43), one gf_node --filter each",
                 fontsize=12)
    fig.tight_layout()
    fig.savefig(out)
    plt.close(fig)
    return True


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    log, out = sys.argv[1], sys.argv[2]
    clouds, meas = {}, {}
    beliefs, truths = read(log, clouds, meas)
    for track, need in ((1, 11), (2, 3), (4, 3)):
        if len(beliefs.get(track, [])) < need:
            sys.exit(f"gf_plots: the log has {len(beliefs.get(track, []))} "
                     f"beliefs of track {track}, need {need}")
    os.makedirs(out, exist_ok=True)
    written = []
    for name, draw in (
            ("fig1_1_ellipses.png", lambda p: fig_1_1(beliefs, p)),
            ("fig1_2_correlation.png", lambda p: fig_1_2(beliefs, p)),
            ("fig2_1_measurement.png", lambda p: fig_2_1(beliefs, p, meas)),
            ("fig4_1_prediction.png", lambda p: fig_4(beliefs, p, False)),
            ("fig4_2_correction.png", lambda p: fig_4(beliefs, p, True))):
        draw(os.path.join(out, name))
        written.append(name)
    if stream_car(beliefs, truths, os.path.join(out, "stream_car.png")):
        written.append("stream_car.png")
    if ex4_three_ways(beliefs, clouds, os.path.join(out, "ex4_three_ways.png")):
        written.append("ex4_three_ways.png")
    for name in written:
        print(os.path.join(out, name))


if __name__ == "__main__":
    main()
