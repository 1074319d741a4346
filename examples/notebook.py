#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The book's tables from Python, beside FilterPy, and float32 beside
float64 on the GPS example: a notebook as a script (run headless by
python/tests/test_examples.py).

    python examples/notebook.py [--plot DIR]

1. Table 1.1, Figure 1.2 and Table 2.1 (exercises 1 and 2): gaussfilt's
   KF2 in float64 and float32, and FilterPy's KalmanFilter on the same
   model (FilterPy's Q is the book's R, its R the book's Q).
2. Table 4.2 (exercise 4): EKF3 with the built-in forward_turn and meas_x,
   and FilterPy's ExtendedKalmanFilter with the same g and h in numpy.
3. The GPS example (examples/gps8.c's model: 8 states, 4 pseudoranges per
   fix, Earth-sized numbers) through gaussfilt's EKF in both precisions,
   the callbacks computing in the filter's precision as firmware would:
   the float32 position's distance from the float64 one, against the 6 m
   of the sensor noise.

Each section ends with a check line; the last line is "notebook: checks
passed" only if every check passed (exit 0). --plot DIR draws Figure 1.2
and the GPS comparison as PNGs (matplotlib).
"""
import argparse
import math
import sys

import numpy as np
from filterpy.kalman import ExtendedKalmanFilter, KalmanFilter

import gaussfilt
from gaussfilt import float32, float64

failed = []


def check(what, ok):
    print("  check: %s: %s" % (what, "ok" if ok else "FAILED"))
    if not ok:
        failed.append(what)


def fmt(a, f="%9.4f"):
    return " ".join(f % v for v in np.ravel(a))


# ---- exercises 1 and 2 ---------------------------------------------------

def exercises_1_2():
    print("Table 1.1: the car's belief, t = 0..5 (Sigma: xx xv vv)")
    A, R = np.array([[1.0, 1], [0, 1]]), np.array([[0.25, 0.5], [0.5, 1]])
    fp = KalmanFilter(dim_x=2, dim_z=1)
    fp.x, fp.P, fp.F, fp.Q = np.zeros(2), np.zeros((2, 2)), A, R
    fp.H, fp.R = np.array([[1.0, 0]]), np.array([[10.0]])
    kfs = {m: m.KF2([0, 0], np.zeros((2, 2))) for m in (float64, float32)}
    car = {m: m.KF2Model(A=A, R=R) for m in kfs}
    rho = {m: [] for m in kfs}
    rho_fp = []
    print("  %2s %-30s %-30s %-30s" % ("t", "float64", "float32", "FilterPy"))
    worst = 0.0
    for t in range(0, 11):
        if t:
            fp.predict()
            for m, kf in kfs.items():
                kf.predict(car[m])
                rho[m].append(m.correlation(kf.sigma))
            rho_fp.append(fp.P[0, 1] / math.sqrt(fp.P[0, 0] * fp.P[1, 1]))
        s = {m: kf.sigma for m, kf in kfs.items()}
        worst = max(worst, np.abs(s[float64] - fp.P).max())
        if t <= 5:
            print("  %2d %-30s %-30s %-30s" % (
                t, fmt(s[float64][[0, 0, 1], [0, 1, 1]]),
                fmt(s[float32][[0, 0, 1], [0, 1, 1]]),
                fmt(fp.P[[0, 0, 1], [0, 1, 1]])))
        if t == 5:
            sigma5 = s[float64].copy()
    check("Table 1.1 at t = 5 is ((41.25, 12.5), (12.5, 5)) to 1e-12",
          np.abs(sigma5 - [[41.25, 12.5], [12.5, 5]]).max() <= 1e-12 * 41.25)
    check("FilterPy's Sigma within 1e-12 of float64's (%.1g)" % worst,
          worst <= 1e-12)

    print("Figure 1.2: rho_t = Sigma_xv / sqrt(Sigma_xx Sigma_vv), t = 1..10")
    print("  float64  " + fmt(rho[float64], "%6.3f"))
    print("  float32  " + fmt(rho[float32], "%6.3f"))
    print("  FilterPy " + fmt(rho_fp, "%6.3f"))
    try:
        float64.correlation(np.zeros((2, 2)))
        check("rho_0 undefined", False)
    except gaussfilt.Undefined:
        print("  t = 0: undefined (both variances zero): gaussfilt.Undefined")
    check("rho falls from 1 to 0.867 at t = 10, above sqrt(3)/2",
          round(rho[float64][0], 3) == 1.0 and
          round(rho[float64][9], 3) == 0.867 and
          rho[float32][9] > math.sqrt(3) / 2)

    print("Table 2.1: z = 5 (variance 10) at t = 5")
    kfs = {m: m.KF2([0, 0], np.zeros((2, 2))) for m in (float64, float32)}
    fp.x, fp.P = np.zeros(2), np.zeros((2, 2))
    for _ in range(5):
        fp.predict()
        for m, kf in kfs.items():
            kf.predict(car[m])
    fp.update(np.array([5.0]))
    for m, kf in kfs.items():
        kf.update(m.KF2Meas(C=[[1, 0]], Q=[[10]]), [5])
        print("  %-8s mu = %s  Sigma = %s  NIS = %.4f" % (
            m.dtype.name, fmt(kf.mu), fmt(kf.sigma[[0, 0, 1], [0, 1, 1]]),
            kf.nis))
    print("  %-8s mu = %s  Sigma = %s" % (
        "FilterPy", fmt(fp.x), fmt(fp.P[[0, 0, 1], [0, 1, 1]])))
    mu = kfs[float64].mu
    check("mu = (4.02, 1.22) as the worked solutions, FilterPy within 1e-12",
          [round(v, 2) for v in mu] == [4.02, 1.22] and
          np.abs(mu - fp.x).max() <= 1e-12)
    return rho


# ---- exercise 4 --------------------------------------------------------------

def exercise_4():
    print("Table 4.2: EKF3, move 1 forward (R = 0), then see x = -0.7")
    S0 = np.diag([0.01, 0.01, 10000.0])
    fp = ExtendedKalmanFilter(dim_x=3, dim_z=1)
    fp.x, fp.P, fp.Q = np.zeros(3), S0.copy(), np.zeros((3, 3))
    th = 0.0
    fp.F = np.array([[1, 0, -math.sin(th)], [0, 1, math.cos(th)], [0, 0, 1]])

    def predict_x(u=0):
        fp.x = np.array([fp.x[0] + math.cos(fp.x[2]),
                         fp.x[1] + math.sin(fp.x[2]), fp.x[2]])
    fp.predict_x = predict_x
    fp.predict()
    fp_pred = fp.P.copy()
    fp.update(np.array([-0.7]), lambda x: np.array([[1.0, 0, 0]]),
              lambda x: x[:1], R=np.array([[0.01]]))
    for m in (float64, float32):
        ekf = m.EKF3([0, 0, 0], S0)
        ekf.predict(m.EKF3Motion(m.forward_turn, np.zeros((3, 3))), [1, 0])
        pred = ekf.sigma
        ekf.update(m.EKF3Meas(m.meas_x, [[0.01]]), [-0.7])
        print("  %-8s predicted Sigma_yy %.2f; corrected mu = %s, "
              "Sigma_xx = %.5f" % (m.dtype.name, pred[1, 1], fmt(ekf.mu),
                                   ekf.sigma[0, 0]))
        if m is float64:
            ok = (np.abs(ekf.mu - fp.x).max() <= 1e-12 and
                  np.abs(ekf.sigma - fp.P).max() <= 1e-9 and
                  np.abs(pred - fp_pred).max() <= 1e-9)
    print("  %-8s predicted Sigma_yy %.2f; corrected mu = %s, "
          "Sigma_xx = %.5f" % ("FilterPy", fp_pred[1, 1], fmt(fp.x),
                               fp.P[0, 0]))
    check("corrected mu = (0.15, 0, 0), FilterPy the same", ok)


# ---- the GPS example in both precisions --------------------------------------

def gps(steps=300, seed=0x6E5A7F01):
    """examples/gps8.c's model; its own simulation (numpy's generator)."""
    SIGMA, QACC, QB, QD, DT = 6.0, 0.1, 0.1, 0.01, 1.0
    RE, RO, GM = 6.371e6, 2.66e7, 3.986004418e14
    rng = np.random.default_rng(seed)
    lat, lon = math.radians(45), math.radians(7)
    up = np.array([math.cos(lat) * math.cos(lon),
                   math.cos(lat) * math.sin(lon), math.sin(lat)])
    east = np.array([-math.sin(lon), math.cos(lon), 0.0])
    north = np.cross(up, east)
    x = np.concatenate([RE * up, 20 * east, [3e4, 2.0]])
    sats = []
    for k in range(4):
        el = 0.1 if k == 0 else math.radians(40)
        az = 2 * math.pi / 3 * (k - 1) + 0.3
        u = math.cos(el) * up + math.sin(el) * (math.cos(az) * north +
                                                math.sin(az) * east)
        u /= np.linalg.norm(u)
        v = np.cross(np.cross(u, rng.normal(size=3)), u)
        sats.append((u, v / np.linalg.norm(v)))
    w = math.sqrt(GM / RO ** 3)
    blk = lambda q: np.array([[q * DT ** 3 / 3, q * DT ** 2 / 2],
                              [q * DT ** 2 / 2, q * DT]])
    R = np.zeros((8, 8))
    for i in range(3):
        R[np.ix_([i, i + 3], [i, i + 3])] = blk(QACC)
    R[6:, 6:] = blk(QD) + np.diag([QB * DT, 0])
    sd0 = np.array([100, 100, 100, 5, 5, 5, 1e5, 10])
    mu0 = x + sd0 * rng.normal(size=8)
    truth, fixes, zs = [], [], []
    L = np.linalg.cholesky(R)
    for k in range(1, steps + 1):
        x = x + np.concatenate([DT * x[3:6], [0, 0, 0], [DT * x[7], 0]])
        x = x + L @ rng.normal(size=8)
        s = np.array([RO * (math.cos(w * k * DT) * u + math.sin(w * k * DT) * v)
                      for u, v in sats])
        truth.append(x.copy())
        fixes.append(s)
        zs.append(np.linalg.norm(s - x[:3], axis=1) + x[6] +
                  SIGMA * rng.normal(size=4))

    out = {}
    for m in (float64, float32):
        dt = m.dtype
        F = np.eye(8, dtype=dt)
        F[[0, 1, 2, 6], [3, 4, 5, 7]] = dt.type(DT)
        cur = {}

        def g(mu, u, F=F):
            return F @ mu, F   # in the filter's precision

        def h(mu, dt=dt):
            d = cur["s"] - mu[:3]
            r = np.sqrt((d * d).sum(axis=1))
            H = np.zeros((4, 8), dt)
            H[:, :3] = -d / r[:, None]
            H[:, 6] = 1
            return r + mu[6], H
        ekf = m.EKF(mu0, np.diag(sd0 ** 2))
        motion = m.EKFMotion(g, R)
        meas = m.EKFMeas(h, np.eye(4) * SIGMA ** 2, n=8)
        pos = []
        for s, z in zip(fixes, zs):
            cur["s"] = s.astype(dt)
            ekf.predict(motion)
            ekf.update(meas, z)
            pos.append(ekf.mu[:3].astype(float))
        out[m] = np.array(pos)
    truth = np.array(truth)
    print("GPS (examples/gps8.c's model): 8 states, 4 pseudoranges of "
          "sigma %.0f m, %d fixes" % (SIGMA, steps))
    err = {m: np.linalg.norm(p - truth[:, :3], axis=1) for m, p in out.items()}
    diff = np.linalg.norm(out[float32] - out[float64], axis=1)
    for m in out:
        print("  %-8s rms position error %.2f m (after 30 fixes)" % (
            m.dtype.name, math.sqrt((err[m][30:] ** 2).mean())))
    print("  float32 vs float64: rms %.2f m, worst %.2f m (step %d)" % (
        math.sqrt((diff ** 2).mean()), diff.max(), diff.argmax() + 1))
    check("both precisions within 3 sigma rms of the truth",
          all(math.sqrt((e[30:] ** 2).mean()) < 3 * SIGMA for e in err.values()))
    check("float32 within the sensor noise (%.0f m) of float64" % SIGMA,
          diff[30:].max() < SIGMA)
    return err, diff


def plot(directory, rho, err, diff):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 3.5))
    t = np.arange(1, 11)
    ax.plot(t, rho[float64], "o-", label="float64")
    ax.plot(t, rho[float32], "x--", label="float32")
    ax.axhline(math.sqrt(3) / 2, color="grey", ls=":", label="sqrt(3)/2")
    ax.set_xlabel("t")
    ax.set_ylabel("rho_t")
    ax.set_title("Figure 1.2: correlation of position and velocity")
    ax.legend()
    fig.tight_layout()
    fig.savefig("%s/figure_1_2_python.png" % directory, dpi=100)
    fig, ax = plt.subplots(figsize=(7, 3.5))
    for m, e in err.items():
        ax.semilogy(np.arange(1, len(e) + 1), e, label=m.dtype.name + " error")
    ax.semilogy(np.arange(1, len(diff) + 1), diff, label="float32 - float64")
    ax.set_xlabel("fix")
    ax.set_ylabel("m")
    ax.set_title("GPS: position error, float32 beside float64")
    ax.legend()
    fig.tight_layout()
    fig.savefig("%s/gps_precisions.png" % directory, dpi=100)
    print("drew %s/figure_1_2_python.png and %s/gps_precisions.png" % (
        directory, directory))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plot", metavar="DIR", help="draw the figures here")
    a = ap.parse_args()
    rho = exercises_1_2()
    exercise_4()
    err, diff = gps()
    if a.plot:
        plot(a.plot, rho, err, diff)
    if failed:
        print("notebook: %d check(s) failed: %s" % (len(failed),
                                                    "; ".join(failed)))
        return 1
    print("notebook: checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
