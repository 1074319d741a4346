# SPDX-License-Identifier: MIT
"""The last accepted update's S, gain K and loglik on every Gaussian
belief (KF2, EKF3, UKF3, KF, EKF), in both precisions: None (nan) before
any update; each equal to the formulas of docs/python.md computed here in
numpy from the covariance read before the update (UKF3 with a linear h,
whose unscented S and K are these; float64 within 1e-12, float32 within
1e-5, both relative to max(1, |value|)); kept bit for bit through a refused update (gated, not
finite, a wrong shape, a callback's exception, a run that fails: the
belief unchanged too); a run leaves its last update's; cleared by reset;
kept by pickle and copy. test_filterpy.py compares them with FilterPy."""
import copy
import math
import pickle

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [float32, float64]
TOL = {float32: 1e-5, float64: 1e-12}


def bilinear_h(mu):  # a module-level Python model: picklable
    return (np.array([mu[0] * mu[1], mu[2]]),
            np.array([[mu[1], mu[0], 0.0], [0.0, 0.0, 1.0]]))


def drift_g(mu, u):
    return mu + 0.1, np.eye(len(mu))


def cases(gf):
    """(name, belief, one prediction, measurement, H at mu_bar, z) per
    family: a prediction, then the update whose S, K and loglik are read."""
    kf2 = gf.KF2(mu=[0, 1], sigma=[[2, 0.5], [0.5, 1]])
    car = gf.KF2Model(A=[[1, 1], [0, 1]], R=[[0.25, 0.5], [0.5, 1]])
    both = gf.KF2Meas(C=[[1, 0], [0.5, 1]], Q=[[2, 0.3], [0.3, 1]])
    ekf3 = gf.EKF3(mu=[0, 0, 3.0], sigma=np.diag([1, 1, 0.1]))
    turn = gf.EKF3Motion(g=gf.forward_turn, R=np.eye(3) * 0.01)
    xy = gf.EKF3Meas(h=gf.meas_xy, Q=[[1, 0.2], [0.2, 0.5]])
    kf = gf.KF(mu=[0, 1, 0, 1], sigma=np.eye(4) * 2)
    cv = gf.KFModel(A=np.kron(np.eye(2), [[1, 1], [0, 1]]),
                    R=np.eye(4) * 0.1)
    # S's first column largest below the diagonal: elimination pivots
    pos = gf.KFMeas(C=[[0.1, 0, 0, 0], [1, 0, 1, 0.5]], Q=np.diag([0.01, 0.7]))
    ekf = gf.EKF(mu=[1, 2, 0.5], sigma=np.diag([1, 0.5, 0.2]))
    drift = gf.EKFMotion(g=drift_g, R=np.eye(3) * 0.01)
    bil = gf.EKFMeas(h=bilinear_h, Q=np.eye(2) * 0.3, n=3)
    # the unscented S of a linear h is H Sigma_bar H^T + Q, its gain
    # Sigma_bar H^T S^-1 (the points' second moment is Sigma_bar)
    ukf3 = gf.UKF3(mu=[0, 0, 3.0], sigma=[[1, 0.3, 0], [0.3, 1, 0.1],
                                          [0, 0.1, 0.1]], alpha=0.5, kappa=1)
    return [
        ("UKF3", ukf3, lambda f: f.predict(turn, u=[1, 0.3]), xy,
         lambda mu: np.eye(2, 3), [-0.8, 0.3]),
        ("KF2", kf2, lambda f: f.predict(car), both,
         lambda mu: np.asarray(both.C, float), [1.5, 0.2]),
        ("EKF3", ekf3, lambda f: f.predict(turn, u=[1, 0.3]), xy,
         lambda mu: np.eye(2, 3), [-0.8, 0.3]),
        ("KF", kf, lambda f: f.predict(cv), pos,
         lambda mu: np.asarray(pos.C, float), [1.2, 2.1]),
        ("EKF", ekf, lambda f: f.predict(drift), bil,
         lambda mu: bilinear_h(mu)[1], [2.9, 0.4]),
    ]


def close(a, b, tol):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a.shape == b.shape and bool(
        np.all(np.abs(a - b) <= tol * max(1.0, float(np.abs(b).max()))))


def snapshot(f):
    return f.__getstate__(), f.S, f.K, f.loglik


def unchanged(f, snap):
    st, S, K, ll = snap
    return (f.__getstate__() == st
            and (S is None and f.S is None or np.array_equal(f.S, S))
            and (K is None and f.K is None or np.array_equal(f.K, K))
            and (math.isnan(ll) and math.isnan(f.loglik) or f.loglik == ll))


@pytest.mark.parametrize("gf", MODS)
def test_none_before_any_update(gf):
    for name, f, predict, meas, _, _ in cases(gf):
        assert f.S is None and f.K is None and math.isnan(f.loglik), name
        predict(f)
        assert f.S is None and f.K is None and math.isnan(f.loglik), name


@pytest.mark.parametrize("gf", MODS)
def test_the_formulas(gf):
    for name, f, predict, meas, H_at, z in cases(gf):
        predict(f)
        P = np.asarray(f.sigma, float)  # Sigma_bar, as the library keeps it
        H = H_at(np.asarray(f.mu, float))
        Q = np.asarray(meas.Q, float)
        f.update(meas, z)
        S = H @ P @ H.T + Q
        K = P @ H.T @ np.linalg.inv(S)
        y = np.asarray(f.innovation, float)
        nis = float(y @ np.linalg.solve(S, y))
        sign, logdet = np.linalg.slogdet(S)
        loglik = -0.5 * (nis + logdet + len(y) * math.log(2 * math.pi))
        assert sign > 0
        assert f.S.dtype == gf.dtype and f.K.dtype == gf.dtype, name
        assert f.S.shape == (len(y), len(y)), name
        assert f.K.shape == (len(P), len(y)), name
        assert close(f.S, S, TOL[gf]), (name, f.S, S)
        assert close(f.K, K, TOL[gf]), (name, f.K, K)
        assert close(f.loglik, loglik, TOL[gf]), (name, f.loglik, loglik)
        assert type(f.loglik) is float


@pytest.mark.parametrize("gf", MODS)
def test_refused_updates_keep_the_last(gf):
    for name, f, predict, meas, _, z in cases(gf):
        predict(f)
        f.update(meas, z)
        snap = snapshot(f)
        m = len(z)
        for bad in ([np.inf] * m, [np.nan] * m, [1.0] * (m + 1), "1.5",
                    None):
            with pytest.raises(gaussfilt.GaussfiltError):
                f.update(meas, bad)
            assert unchanged(f, snap), (name, bad)
    # a gate
    kf = gf.KF(mu=[0, 0], sigma=np.eye(2))
    kf.update(gf.KFMeas(C=[[1, 0]], Q=[[1]]), [0.5])
    snap = snapshot(kf)
    with pytest.raises(gaussfilt.Gated):
        kf.update(gf.KFMeas(C=[[1, 0]], Q=[[1]], gate=1.0), [30.0])
    assert unchanged(kf, snap)
    # a measurement callback that raises, and one whose H is not finite
    ekf = gf.EKF(mu=[1, 2, 0.5], sigma=np.eye(3))
    ekf.update(gf.EKFMeas(h=bilinear_h, Q=np.eye(2), n=3), [2, 0.5])
    snap = snapshot(ekf)

    def raising(mu):
        raise KeyError("h")

    def nan_H(mu):
        return bilinear_h(mu)[0], np.full((2, 3), np.nan)
    with pytest.raises(KeyError):
        ekf.update(gf.EKFMeas(h=raising, Q=np.eye(2), n=3), [2, 0.5])
    with pytest.raises(gaussfilt.GaussfiltError):
        ekf.update(gf.EKFMeas(h=nan_H, Q=np.eye(2), n=3), [2, 0.5])
    assert unchanged(ekf, snap)


@pytest.mark.parametrize("gf", MODS)
def test_run_leaves_its_last_update(gf):
    model = gf.KFModel(A=[[1, 1], [0, 1]], R=np.eye(2) * 0.1)
    meas = gf.KFMeas(C=[[1, 0]], Q=[[2]])
    z = np.array([[1.0], [2.2], [np.nan], [3.1], [np.nan]])
    a, b = gf.KF(mu=[0, 0], sigma=np.eye(2)), gf.KF(mu=[0, 0], sigma=np.eye(2))
    a.run(model, meas, z=z)
    for zk in z:
        b.predict(model)
        if not np.isnan(zk[0]):
            b.update(meas, zk)
    assert a.__getstate__() == b.__getstate__()
    assert np.array_equal(a.S, b.S) and np.array_equal(a.K, b.K)
    assert a.loglik == b.loglik
    # a run that fails part way puts them back with the belief
    snap = snapshot(a)
    with pytest.raises(gaussfilt.NonFinite) as e:
        a.run(model, meas, z=np.array([[1.0], [2.0], [np.inf]]))
    assert e.value.step == 2
    assert unchanged(a, snap)
    # a gated step of a run keeps the one before it
    gated = gf.KFMeas(C=[[1, 0]], Q=[[2]], gate=3.0)
    c = gf.KF(mu=[0, 0], sigma=np.eye(2))
    _, _, _, status = c.run(model, gated, z=[[0.5], [50.0]])
    assert list(status) == [0, -5]
    d = gf.KF(mu=[0, 0], sigma=np.eye(2))
    d.run(model, gated, z=[[0.5]])
    assert np.array_equal(c.S, d.S) and c.loglik == d.loglik


@pytest.mark.parametrize("gf", MODS)
def test_reset_clears_setters_keep(gf):
    for name, f, predict, meas, _, z in cases(gf):
        predict(f)
        f.update(meas, z)
        S, ll = f.S, f.loglik
        f.mu = f.mu + 1
        f.sigma = f.sigma * 2
        assert np.array_equal(f.S, S) and f.loglik == ll, name
        f.reset(f.mu, f.sigma)
        assert f.S is None and f.K is None and math.isnan(f.loglik), name


@pytest.mark.parametrize("gf", MODS)
def test_pickle_and_copy_keep_them(gf):
    for name, f, predict, meas, _, z in cases(gf):
        predict(f)
        f.update(meas, z)
        for twin in (pickle.loads(pickle.dumps(f)), copy.copy(f),
                     copy.deepcopy(f)):
            assert np.array_equal(twin.S, f.S), name
            assert np.array_equal(twin.K, f.K), name
            assert twin.loglik == f.loglik, name
            assert twin.__getstate__() == f.__getstate__(), name
        st = f.__getstate__()
        # a state with the innovation alone: the NIS, no S to read
        plain = type(f).__new__(type(f))
        size = len(gf.KF(mu=[0], sigma=[[1]]).__getstate__()[3])
        plain.__setstate__(st[:3] + (st[3][:size],) + st[4:])
        assert plain.nis == f.nis and plain.S is None, name
        assert math.isnan(plain.loglik), name
        # a record of the wrong length, or one whose prior is not a belief
        for bad in (st[3][:-1], st[3] + b"\0",
                    st[3][:size] + bytes(len(st[3]) - size)):
            twin = copy.copy(f)
            snap = snapshot(twin)
            with pytest.raises(gaussfilt.BadArgument, match="last update"):
                twin.__setstate__(st[:3] + (bad,) + st[4:])
            assert unchanged(twin, snap), name
