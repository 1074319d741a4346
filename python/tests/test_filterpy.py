# SPDX-License-Identifier: MIT
"""FilterPy, the reference Python Kalman filter, agrees with the package in
float64 on the bit-identity scenarios (scenarios.py), to the tolerance
below, after every step. FilterPy's names are the other way round: its Q
is the book's R (process noise), its R the book's Q (measurement noise).

FilterPy computes Sigma itself (Joseph form, no factors) and has neither
constant terms nor gates: c is added to its mean and subtracted from z
here, and a gated update is checked against the NIS of FilterPy's prior
and not applied. TOL: |ours - FilterPy's| <= TOL max(1, max |FilterPy's|)
per belief. The largest seen (printed with pytest -s): below 1e-14 for
KF2, KF and EKF, 4e-11 for EKF3, whose g uses the library's gf_sincos here
and libm's sin and cos in FilterPy's run.

After every accepted update the last update's S, gain K and loglik agree
with FilterPy's S, K and log_likelihood to TOL the same way (loglik:
|ours - FilterPy's| <= TOL max(1, |FilterPy's|)); a gated update leaves
all three as they were. Largest seen: below 2e-14 for KF2, KF and EKF,
1.1e-10 for EKF3 (its g, as above).
"""
import math

import numpy as np
import pytest
from filterpy.kalman import ExtendedKalmanFilter, KalmanFilter

import gaussfilt
import scenarios as S
from gaussfilt import float64 as gf

TOL = 1e-9
worst = {}


def agree(name, ours_mu, ours_sigma, x, P, angle=None):
    d_mu = np.asarray(ours_mu, float) - np.asarray(x, float)
    if angle is not None:  # EKF3 keeps the heading in (-pi, pi]
        d_mu[angle] = math.remainder(d_mu[angle], 2 * math.pi)
    scale = max(1.0, np.abs(P).max(), np.abs(x).max())
    err = max(np.abs(d_mu).max(), np.abs(ours_sigma - P).max()) / scale
    worst[name] = max(worst.get(name, 0.0), err)
    assert err <= TOL, "%s: relative difference %.3g" % (name, err)


def agree_update(name, ours, fp):
    """The last update's S, K and loglik beside FilterPy's."""
    err = max(np.abs(ours.S - fp.S).max() / max(1.0, np.abs(fp.S).max()),
              np.abs(ours.K - fp.K).max() / max(1.0, np.abs(fp.K).max()),
              abs(ours.loglik - fp.log_likelihood)
              / max(1.0, abs(fp.log_likelihood)))
    worst[name + " update"] = max(worst.get(name + " update", 0.0), err)
    assert err <= TOL, "%s: S, K or loglik differ by %.3g" % (name, err)


def forward_turn(x, u):
    d, phi = u
    G = np.array([[1, 0, -d * math.sin(x[2])], [0, 1, d * math.cos(x[2])],
                  [0, 0, 1]])
    return np.array([x[0] + d * math.cos(x[2]), x[1] + d * math.sin(x[2]),
                     x[2] + phi]), G


@pytest.mark.parametrize("family,n", S.FAMILIES)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_filterpy_agrees(family, n, seed):
    ops = S.generate(family, n, seed)
    dt = np.dtype(np.float64)
    g = forward_turn if family == "ekf3" else S.cubic(dt)
    ours = fp = None
    gated = 0
    for code, f in ops:
        if code in (S.OP_KF2_INIT, S.OP_KF_INIT, S.OP_EKF3_INIT, S.OP_EKF_INIT):
            ours = {"kf2": gf.KF2, "kf": gf.KF, "ekf3": gf.EKF3,
                    "ekf": gf.EKF}[family](f["mu"], f["sigma"])
            fp = (KalmanFilter if family in ("kf2", "kf")
                  else ExtendedKalmanFilter)(dim_x=n, dim_z=1)
            fp.x = np.array(f["mu"], float)
            fp.P = np.array(f["sigma"], float)
        elif code in (S.OP_KF2_PREDICT, S.OP_KF_PREDICT):
            nu = f["B"].shape[1]
            model = (gf.KF2Model(f["A"], f["R"], f["B"], f["c"])
                     if family == "kf2" else
                     gf.KFModel(f["A"], f["R"], f["B"] if nu else None, f["c"]))
            ours.predict(model, f["u"])
            fp.predict(u=f["u"], B=f["B"] if nu else None, F=f["A"], Q=f["R"])
            if f["c"] is not None:
                fp.x = fp.x + f["c"]
        elif code in (S.OP_EKF3_PREDICT, S.OP_EKF_PREDICT):
            if family == "ekf3":
                ours.predict(gf.EKF3Motion(gf.forward_turn, f["R"]), f["u"])
            else:
                ours.predict(gf.EKFMotion(g, f["R"]), f["u"])
            x_bar, G = g(fp.x, f["u"])
            fp.F, fp.Q = G, f["R"]
            fp.predict_x = lambda u, x_bar=x_bar: setattr(fp, "x", x_bar)
            fp.predict()
        else:
            m = f["m"]
            c = f.get("c")
            z = np.asarray(f["z"], float) - (c if c is not None else 0)
            if family in ("kf2", "kf"):
                H = f["C"]

                def hx(x, H=H):
                    return H @ x
                meas = (gf.KF2Meas if family == "kf2" else gf.KFMeas)(
                    f["C"], f["Q"], c, f["gate"])
            else:
                h = (S.bilinear(dt, m) if family == "ekf" else
                     (lambda x, m=m: (x[:m], np.eye(m, 3))))
                H = h(fp.x)[1]

                def hx(x, h=h):
                    return h(x)[0]
                meas = (gf.EKFMeas(S.bilinear(dt, m), f["Q"], n, 0, f["gate"])
                        if family == "ekf" else
                        gf.EKF3Meas(gf.meas_x if m == 1 else gf.meas_xy,
                                    f["Q"], 0, f["gate"]))
            y = z - hx(fp.x)
            Sm = H @ fp.P @ H.T + f["Q"]
            nis = float(y @ np.linalg.solve(Sm, y))
            kept = ours.S, ours.K, ours.loglik
            try:
                ours.update(meas, f["z"])
            except gaussfilt.Gated as e:
                gated += 1
                assert nis > f["gate"] > 0
                assert e.nis == pytest.approx(nis, rel=1e-6)
                # the last accepted update's S, K and loglik are kept
                assert (kept[0] is None and ours.S is None
                        or np.array_equal(kept[0], ours.S))
                assert (kept[1] is None and ours.K is None
                        or np.array_equal(kept[1], ours.K))
                assert (math.isnan(kept[2]) and math.isnan(ours.loglik)
                        or kept[2] == ours.loglik)
                continue
            assert not (f["gate"] and nis > f["gate"] * (1 + 1e-9))
            if family in ("kf2", "kf"):
                fp.update(z, R=f["Q"], H=H)
            else:
                fp.update(z, lambda x, h=h: h(x)[1], hx, R=f["Q"])
            assert ours.nis == pytest.approx(nis, rel=1e-6, abs=1e-9)
            agree_update("%s n=%d" % (family, n), ours, fp)
        agree("%s n=%d" % (family, n), ours.mu, ours.sigma, fp.x, fp.P,
              angle=2 if family == "ekf3" else None)
    print("%s n=%d seed %d: worst relative difference %.2g (S, K, loglik: "
          "%.2g), %d gated" % (family, n, seed, worst["%s n=%d" % (family, n)],
                               worst.get("%s n=%d update" % (family, n), 0.0),
                               gated))


def range_bearing(x):  # landmark at (4, 3): (range, bearing), an angle
    dx, dy = 4.0 - x[0], 3.0 - x[1]
    return (np.array([math.hypot(dx, dy), math.atan2(dy, dx) - x[2]]),
            np.zeros((2, 3)))


def wrapped(d, mask):
    d = np.array(d, float)
    for i in range(len(d)):
        if mask >> i & 1:
            d[i] = math.remainder(d[i], 2 * math.pi)
    return d


@pytest.mark.parametrize("params", [(1.0, 2.0, 0.0), (0.5, 2.0, 1.0),
                                    (0.2, 0.0, 0.5)])
@pytest.mark.parametrize("h", ["meas_xy", "meas_x", "range_bearing"])
def test_filterpy_agrees_on_ukf3_updates(params, h):
    """UKF3's S, K and loglik beside FilterPy's UnscentedKalmanFilter with
    MerweScaledSigmaPoints of the same alpha, beta and kappa, drawn from
    the same mu_bar and Sigma_bar (Table 3.4 draws the update's points
    afresh; FilterPy's update reuses its prediction's, so they are set
    here), the heading and the bearing's residuals wrapped and z_hat's
    mean taken about the centre's image as the library takes it."""
    from filterpy.kalman import MerweScaledSigmaPoints, UnscentedKalmanFilter
    alpha, beta, kappa = params
    rng = np.random.default_rng(7)
    mask = 2 if h == "range_bearing" else 0
    m = 1 if h == "meas_x" else 2
    Q = np.array([[0.05, 0.01], [0.01, 0.03]])[:m, :m]
    fn = range_bearing if h == "range_bearing" else getattr(gf, h)
    meas = gf.EKF3Meas(fn, Q, angle_mask=mask)
    def hx(s):  # z alone, as FilterPy's h gives it
        return range_bearing(s)[0] if h == "range_bearing" else s[:m]
    motion = gf.EKF3Motion(gf.forward_turn, np.diag([0.02, 0.02, 0.01]))
    ours = gf.UKF3([0.5, -0.2, 0.4], np.diag([0.2, 0.3, 0.1]), alpha=alpha,
                   beta=beta, kappa=kappa)
    points = MerweScaledSigmaPoints(3, alpha=alpha, beta=beta, kappa=kappa)

    def z_mean(sigmas, Wm):  # about the centre's image, as ukf3.h says
        d = np.array([wrapped(s - sigmas[0], mask) for s in sigmas])
        return wrapped(sigmas[0] + Wm @ d, mask)
    name = "ukf3 %s alpha=%g" % (h, alpha)
    x = np.array([0.5, -0.2, 0.4])
    for k in range(40):
        u = [0.3, rng.uniform(-0.3, 0.3)]
        ours.predict(motion, u)
        x = forward_turn(x, u)[0]
        mu, P = np.asarray(ours.mu, float), np.asarray(ours.sigma, float)
        z = wrapped(hx(x) + rng.normal(size=m) * 0.2, mask)
        ours.update(meas, z)
        fp = UnscentedKalmanFilter(3, m, 1.0, hx=hx,
                                   fx=lambda s, dt: s, points=points,
                                   z_mean_fn=z_mean,
                                   residual_z=lambda a, b: wrapped(a - b,
                                                                   mask))
        fp.x, fp.P, fp.R = mu.copy(), P.copy(), Q.copy()
        fp.sigmas_f = points.sigma_points(mu, P)
        fp.update(z)
        assert ours.nis == pytest.approx(
            float(fp.y @ np.linalg.solve(fp.S, fp.y)), rel=1e-9)
        agree_update(name, ours, fp)
    print("%s: S, K, loglik worst relative difference %.2g"
          % (name, worst[name + " update"]))
