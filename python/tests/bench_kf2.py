#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The package's speed, printed (never asserted): KF2 on the C benchmark's
workload (Table 1.1's car, a position measurement of variance 10 at every
step; python/tests/replay/replay.c --bench-kf2 is the C loop):

- the C loop, ns per predict + update (gf_replay --bench-kf2);
- the package, one predict and one update call per step, and its
  overhead over the C step;
- the package's batch entry, KF2.run, over arrays of z;
- FilterPy's KalmanFilter, predict + update, on the same workload;
- KF of n = 4 (a constant-velocity target in the plane, its position
  measured), a call each and KF.run;
- an update alone with z in each form the package reads in place (a
  list, a tuple, Python and numpy scalars, the other precision's array),
  beside an array of the module's own type.

Every figure is the median of --repeat timed runs (default 7).

    python python/tests/bench_kf2.py [--replay PATH_TO_gf_replay] [--steps N]
                                     [--repeat R]

scripts/bench-python builds gf_replay (double) and runs this.
"""
import argparse
import statistics
import subprocess
import time

import numpy as np

import gaussfilt
from gaussfilt import float64 as gf


REPEAT = 7


def median_of(fn, repeat=None):
    """The median time of repeat calls of fn, in seconds."""
    times = []
    for _ in range(repeat or REPEAT):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    global REPEAT
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", help="gf_replay (double) for the C loop")
    ap.add_argument("--steps", type=int, default=200000)
    ap.add_argument("--repeat", type=int, default=REPEAT,
                    help="timed runs of each figure; the median is printed")
    a = ap.parse_args()
    N = a.steps
    REPEAT = max(1, a.repeat)
    z = (np.arange(N) % 17 - 8.0).reshape(N, 1)

    car = gf.KF2Model(A=[[1, 1], [0, 1]], R=[[0.25, 0.5], [0.5, 1]])
    gps = gf.KF2Meas(C=[[1, 0]], Q=[[10]])
    zs = [np.array(r) for r in z]

    def steps():
        kf = gf.KF2([0, 0], np.eye(2))
        predict, update = kf.predict, kf.update
        for zk in zs:
            predict(car)
            update(gps, zk)

    def batch():
        gf.KF2([0, 0], np.eye(2)).run(car, gps, z=z)

    c_ns = None
    if a.replay:
        out = subprocess.run([a.replay, "--bench-kf2", str(N)], check=True,
                             capture_output=True, text=True).stdout
        c_ns = statistics.median(float(subprocess.run(
            [a.replay, "--bench-kf2", str(N)], check=True, capture_output=True,
            text=True).stdout.split(":")[1].split()[0]) for _ in range(REPEAT))
        print(out.strip())
    py_ns = median_of(steps) / N * 1e9
    batch_ns = median_of(batch) / N * 1e9

    from filterpy.kalman import KalmanFilter
    fk = KalmanFilter(dim_x=2, dim_z=1)
    fk.F = np.array([[1.0, 1], [0, 1]])
    fk.Q = np.array([[0.25, 0.5], [0.5, 1]])   # FilterPy's Q: process noise
    fk.H = np.array([[1.0, 0]])
    fk.R = np.array([[10.0]])                   # FilterPy's R: measurement
    M = min(N, 20000)

    def filterpy_steps():
        fk.x, fk.P = np.zeros(2), np.eye(2)
        for zk in zs[:M]:
            fk.predict()
            fk.update(zk)
    fp_ns = median_of(filterpy_steps, 3) / M * 1e9

    print("KF2, predict + update, %d steps (median of %d; FilterPy: %d "
          "steps, median of 3):" % (N, REPEAT, M))
    if c_ns is not None:
        print("  C loop (gf_replay --bench-kf2)   %8.3f us per step" % (c_ns / 1e3))
    print("  Python, a call each              %8.3f us per step" % (py_ns / 1e3))
    if c_ns is not None:
        print("    its overhead over the C step   %8.3f us" % ((py_ns - c_ns) / 1e3))
    print("  Python, KF2.run (batch)          %8.3f us per step" % (batch_ns / 1e3))
    if c_ns is not None:
        print("    batch / C loop                 %8.2f x" % (batch_ns / c_ns))
    print("  FilterPy KalmanFilter            %8.3f us per step" % (fp_ns / 1e3))
    print("    FilterPy / Python calls        %8.1f x" % (fp_ns / py_ns))
    print("    FilterPy / batch               %8.1f x" % (fp_ns / batch_ns))
    cv = gf.KFModel(A=[[1, 0, 1, 0], [0, 1, 0, 1], [0, 0, 1, 0],
                       [0, 0, 0, 1]], R=np.diag([0.25, 0.25, 1.0, 1.0]))
    pos = gf.KFMeas(C=[[1, 0, 0, 0], [0, 1, 0, 0]], Q=np.eye(2) * 10)
    z4 = np.hstack([z, -z])
    z4s = [np.array(r) for r in z4]
    K = N // 4

    def kf4_steps():
        kf = gf.KF(np.zeros(4), np.eye(4))
        predict, update = kf.predict, kf.update
        for zk in z4s[:K]:
            predict(cv)
            update(pos, zk)

    def kf4_batch():
        gf.KF(np.zeros(4), np.eye(4)).run(cv, pos, z=z4[:K])
    kf4_ns = median_of(kf4_steps) / K * 1e9
    kf4_batch_ns = median_of(kf4_batch) / K * 1e9
    print("KF, n = 4, predict + update (a position of 2), %d steps (median "
          "of %d):" % (K, REPEAT))
    print("  Python, a call each              %8.3f us per step" % (kf4_ns / 1e3))
    print("  Python, KF.run (batch)           %8.3f us per step"
          % (kf4_batch_ns / 1e3))
    print("update alone, by the form z comes in (median of %d runs of %d "
          "calls; x: over an array of the module's type, and over a "
          "float64 array):" % (REPEAT, N // 4))
    for mod in (gf, gaussfilt.float32):
        kf = mod.KF2([0, 0], np.eye(2))
        meas = mod.KF2Meas(C=[[1, 0]], Q=[[10]])
        forms = [("an array of the module's type",
                  np.array([0.5], dtype=mod.dtype)),
                 ("a float64 array", np.array([0.5])),
                 ("a float32 array", np.array([0.5], dtype=np.float32)),
                 ("a list", [0.5]), ("a tuple", (0.5,)),
                 ("a list of ints", [1]),
                 ("a list of numpy.float64", [np.float64(0.5)]),
                 ("a float", 0.5), ("an int", 1),
                 ("a numpy.float64", np.float64(0.5)),
                 ("a numpy.float32", np.float32(0.5)),
                 ("an int16 array (numpy converts)",
                  np.array([1], dtype=np.int16))]
        times = {}
        for label, zf in forms:
            update = kf.update

            def calls(zf=zf, update=update, meas=meas):
                for _ in range(N // 4):
                    update(meas, zf)
            times[label] = median_of(calls) / (N // 4) * 1e9
        own, f64 = times[forms[0][0]], times["a float64 array"]
        for label, ns in times.items():
            print("  %s, z as %-33s %7.3f us  %5.2fx  %5.2fx"
                  % (mod.__name__.split(".")[1], label, ns / 1e3, ns / own,
                     ns / f64))


if __name__ == "__main__":
    main()
