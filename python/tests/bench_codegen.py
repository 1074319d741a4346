#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""A generated model's speed in the notebook, printed (never asserted):
the bicycle of docs/codegen.md (5 states; GPS position and the compass at
every step), one predict and two updates per step, in float64:

- the model built by gaussfilt.codegen.build, handed to the EKF as C
  (its callables' capsules: no Python in the step);
- the same, the whole run in one EKF.run (motion and GPS only: run takes
  one measurement), without the GIL;
- the same C called through Python: g and h as Python callables that call
  the generated functions through ctypes (the path before the capsule);
- g and h written in Python with numpy, the same model by hand.

Every figure is the median of --repeat timed runs (default 7); the two
paths through Python run min(steps, 20000) steps.

    python python/tests/bench_codegen.py [--steps N] [--repeat R]

scripts/bench-python runs this after bench_kf2.py when SymPy is there.
"""
import argparse
import statistics
import tempfile
import time

import numpy as np

from gaussfilt import codegen as cg
from gaussfilt import float64 as gf

from test_codegen import bicycle


def median_of(fn, repeat):
    """The median time of repeat calls of fn, in seconds."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


class ThroughPython:
    """A built callback behind a Python function: the filter calls Python,
    which calls the C through ctypes."""

    def __init__(self, fn):
        self.fn = fn

    def __call__(self, *args):
        return self.fn(*args)


L = 2.5


def g_numpy(mu, u):
    x, y, th, v, de = mu
    a, w, dt = u
    s, c = np.sin(th), np.cos(th)
    sd, cd = np.sin(de), np.cos(de)
    mu_bar = np.array([x + v * c * dt, y + v * s * dt,
                       th + v / L * sd / cd * dt, v + a * dt, de + w * dt])
    G = np.eye(5)
    G[0, 2], G[0, 3] = -v * s * dt, c * dt
    G[1, 2], G[1, 3] = v * c * dt, s * dt
    G[2, 3] = sd / cd * dt / L
    G[2, 4] = v * dt / (L * cd * cd)
    return mu_bar, G


H_GPS = np.eye(5)[:2]
H_COMPASS = np.eye(5)[2:3]


def h_gps(mu):
    return mu[:2], H_GPS


def h_compass(mu):
    return mu[2:3], H_COMPASS


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200000)
    ap.add_argument("--repeat", type=int, default=7,
                    help="timed runs of each figure; the median is printed")
    a = ap.parse_args()
    N, R = a.steps, max(1, a.repeat)
    M = min(N, 20000)
    work = tempfile.mkdtemp(prefix="bench_codegen_")
    b = cg.build(bicycle(), work)
    b.set_params(L=L, lx=10, ly=5)
    rng = np.random.default_rng(1)
    u = np.column_stack([rng.normal(size=N) * 0.2, rng.normal(size=N) * 0.1,
                         np.full(N, 0.1)])
    z = np.cumsum(rng.normal(size=(N, 2)), axis=0) * 0.1
    zc = np.zeros((N, 1)) + 0.3
    us, zs, zcs = list(u), list(z), list(zc)
    R5 = b.R(0.1)
    ways = {
        "built model, C callbacks": (b.motion(0.1), b.meas("gps"),
                                     b.meas("compass")),
        "built model through ctypes": (
            gf.EKFMotion(ThroughPython(b.g), R5),
            gf.EKFMeas(ThroughPython(b.h["gps"]), b.Q("gps"), 5),
            gf.EKFMeas(ThroughPython(b.h["compass"]), b.Q("compass"), 5,
                       angle_mask=1)),
        "Python callbacks (numpy)": (
            gf.EKFMotion(g_numpy, R5), gf.EKFMeas(h_gps, b.Q("gps"), 5),
            gf.EKFMeas(h_compass, b.Q("compass"), 5, angle_mask=1)),
    }
    times = {}
    for label, (motion, gps, compass) in ways.items():
        steps = N if label.endswith("C callbacks") else M

        def run(motion=motion, gps=gps, compass=compass, steps=steps):
            ekf = gf.EKF(mu=[0, 0, 0.3, 2, 0.1], sigma=np.eye(5),
                         angles=b.angles)
            predict, update = ekf.predict, ekf.update
            for t in range(steps):
                predict(motion, us[t])
                update(gps, zs[t])
                update(compass, zcs[t])
        times[label] = median_of(run, R) / steps * 1e9
    motion, gps = b.motion(0.1), b.meas("gps")

    def batch():
        gf.EKF(mu=[0, 0, 0.3, 2, 0.1], sigma=np.eye(5),
               angles=b.angles).run(motion, gps, u=u, z=z)
    batch_ns = median_of(batch, R) / N * 1e9
    c = times["built model, C callbacks"]
    print("EKF, the bicycle (5 states), predict + GPS + compass updates per "
          "step, float64 (median of %d; through Python: %d steps, else %d):"
          % (R, M, N))
    for label, ns in times.items():
        print("  %-34s %8.3f us per step  %6.1fx" % (label, ns / 1e3, ns / c))
    print("  %-34s %8.3f us per step (predict + GPS)"
          % ("built model, EKF.run (batch)", batch_ns / 1e3))


if __name__ == "__main__":
    main()
