# SPDX-License-Identifier: MIT
"""rts_smooth beside FilterPy's rts_smoother on the same filtered run
(KF2 and a 4-state KF, seeded), within 1e-9 relative; the smoother lowers
every variance below the filter's and ends on the filter's last belief;
a run with controls; bad arguments."""
import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

filterpy = pytest.importorskip("filterpy.kalman")


def close(a, b, tol=1e-9):
    scale = max(1.0, float(np.max(np.abs(b))))
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b)))) <= tol * scale


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_kf2_beside_filterpy(seed):
    rng = np.random.default_rng(seed)
    car = float64.KF2Model(A=[[1, 1], [0, 1]], R=[[0.25, 0.5], [0.5, 1]])
    gps = float64.KF2Meas(C=[[1, 0]], Q=[[10]])
    z = np.cumsum(rng.normal(size=(60, 1)), axis=0)
    kf = float64.KF2(mu=[0, 0], sigma=np.eye(2) * 5)
    mu, sigma, _, status = kf.run(car, gps, z=z)
    assert np.all(status == 0)
    ms, ss = gaussfilt.rts_smooth(mu, sigma, car)
    Fs = [np.asarray(car.A)] * len(z)
    Qs = [np.asarray(car.R)] * len(z)
    fx, fP, _, _ = filterpy.rts_smoother(mu.copy(), sigma.copy(), Fs, Qs)
    assert close(ms, fx) and close(ss, fP)
    # smoothing only lowers the variances, and the last step is the filter's
    assert np.all(ss[:, 0, 0] <= sigma[:, 0, 0] + 1e-12)
    assert np.array_equal(ms[-1], mu[-1]) and np.array_equal(ss[-1],
                                                               sigma[-1])


def test_kf4_with_controls_and_float32():
    rng = np.random.default_rng(7)
    A = np.kron(np.eye(2), [[1, 0.5], [0, 1]])
    B = rng.normal(size=(4, 2)) * 0.1
    for gf in (float64, float32):
        model = gf.KFModel(A=A, R=np.eye(4) * 0.01, B=B, c=[0.01, 0, 0, 0])
        meas = gf.KFMeas(C=[[1, 0, 0, 0], [0, 0, 1, 0]], Q=np.eye(2))
        u = rng.normal(size=(40, 2))
        z = rng.normal(size=(40, 2))
        kf = gf.KF(mu=np.zeros(4), sigma=np.eye(4))
        mu, sigma, _, _ = kf.run(model, meas, u=u, z=z)
        ms, ss = gaussfilt.rts_smooth(mu, sigma, model, u=u)
        assert ms.dtype == np.float64 and ss.shape == (40, 4, 4)
        # the same smoother written out by hand
        m64, s64 = mu.astype(float), sigma.astype(float)
        A64, R64 = np.asarray(model.A, float), np.asarray(model.R, float)
        B64, c64 = np.asarray(model.B, float), np.asarray(model.c, float)
        xs, Ps = m64.copy(), s64.copy()
        for k in range(38, -1, -1):
            xb = A64 @ m64[k] + B64 @ u[k + 1] + c64
            Pb = A64 @ s64[k] @ A64.T + R64
            J = s64[k] @ A64.T @ np.linalg.inv(Pb)
            xs[k] = m64[k] + J @ (xs[k + 1] - xb)
            Ps[k] = s64[k] + J @ (Ps[k + 1] - Pb) @ J.T
        assert close(ms, xs) and close(ss, Ps)


def test_bad_arguments():
    car = float64.KF2Model(A=np.eye(2), R=np.eye(2))
    with pytest.raises(gaussfilt.BadArgument, match="mu must be"):
        gaussfilt.rts_smooth(np.zeros(3), np.zeros((3, 2, 2)), car)
    with pytest.raises(gaussfilt.BadArgument, match="KF2Model or KFModel"):
        gaussfilt.rts_smooth(np.zeros((3, 2)), np.zeros((3, 2, 2)),
                             float64.KF2Meas(C=[[1, 0]], Q=[[1]]))
    model = float64.KFModel(A=np.eye(2), R=np.eye(2))
    with pytest.raises(gaussfilt.BadArgument, match="no B"):
        gaussfilt.rts_smooth(np.zeros((3, 2)), np.zeros((3, 2, 2)), model,
                             u=np.zeros((3, 1)))
    with pytest.raises(gaussfilt.BadArgument, match="finite"):
        gaussfilt.rts_smooth(np.full((3, 2), np.nan), np.zeros((3, 2, 2)),
                             car)
