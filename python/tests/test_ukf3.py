# SPDX-License-Identifier: MIT
"""UKF3, the unscented filter, bound with EKF3's conventions, in both
precisions: on linear models it equals EKF3 (UKF_TOL, as tests/test_ukf3.c);
on forward_turn and a bearing-free nonlinear measurement it equals Table
3.4 written out here in numpy (float64, 1e-9 relative); a Python h equal
to a built-in's gives the built-in's bits; run equals one call per step,
bit for bit, and a failed run changes nothing; bad input is refused with
the belief unchanged (and the last update's S, K and loglik with it);
pickle and copy keep every bit; the setters and reset judge as the
constructor does; the repr. S, K and loglik: test_last_update.py, and
test_filterpy.py beside FilterPy's UnscentedKalmanFilter."""
import copy
import math
import pickle

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [float32, float64]
UKF_TOL = {float32: 1e-4, float64: 1e-9}
MU0 = [0.5, -0.3, 0.4]
SIGMA0 = [[0.2, 0.05, 0.01], [0.05, 0.3, -0.02], [0.01, -0.02, 0.05]]
LIN_A = np.array([[1, 0.5, 0], [-0.2, 1, 0.3], [0.05, 0, 1]])


def linear_g(mu, u):  # module level: picklable
    return LIN_A @ mu + np.array([u[0], u[1], 0.0]), LIN_A


def mixed_h(mu):
    """x * y and y: nonlinear, no angle."""
    return (np.array([mu[0] * mu[1], mu[1]]),
            np.array([[mu[1], mu[0], 0.0], [0.0, 1.0, 0.0]]))


def turn_g(mu, u):
    """forward_turn in numpy (libm's sin and cos)."""
    d, phi = u
    c, s = math.cos(mu[2]), math.sin(mu[2])
    return (np.array([mu[0] + d * c, mu[1] + d * s, mu[2] + phi]),
            np.array([[1, 0, -d * s], [0, 1, d * c], [0, 0, 1]]))


def close(a, b, tol):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return bool(np.all(np.abs(a - b) <= tol * max(1.0, np.abs(b).max())))


class Reference:
    """Table 3.4 as the book writes it, in float64 (Cholesky square root,
    the centre's weights as given; no heading here comes near +-pi)."""

    def __init__(self, mu, sigma, alpha=1.0, beta=2.0, kappa=0.0):
        n = 3
        self.mu, self.P = np.array(mu, float), np.array(sigma, float)
        lam = alpha ** 2 * (n + kappa) - n
        self.gamma = math.sqrt(n + lam)
        self.wm = np.full(2 * n + 1, 1 / (2 * (n + lam)))
        self.wc = self.wm.copy()
        self.wm[0] = lam / (n + lam)
        self.wc[0] = self.wm[0] + 1 - alpha ** 2 + beta

    def points(self):
        L = np.linalg.cholesky(self.P)
        return np.array([self.mu] + [self.mu + self.gamma * L[:, i]
                                     for i in range(3)]
                        + [self.mu - self.gamma * L[:, i] for i in range(3)])

    def predict(self, g, u, R):
        Y = np.array([g(x, u)[0] for x in self.points()])
        self.mu = self.wm @ Y
        d = Y - self.mu
        self.P = (self.wc[:, None, None] * np.einsum("ki,kj->kij", d, d)
                  ).sum(0) + R

    def update(self, h, z, Q):
        X = self.points()
        Z = np.array([h(x)[0] for x in X])
        zh = self.wm @ Z
        dz, dx = Z - zh, X - self.mu
        S = (self.wc[:, None, None] * np.einsum("ki,kj->kij", dz, dz)
             ).sum(0) + Q
        Sxz = (self.wc[:, None, None] * np.einsum("ki,kj->kij", dx, dz)
               ).sum(0)
        K = Sxz @ np.linalg.inv(S)
        self.mu = self.mu + K @ (np.asarray(z, float) - zh)
        self.P = self.P - K @ S @ K.T


@pytest.mark.parametrize("gf", MODS)
@pytest.mark.parametrize("alpha,beta,kappa", [(1, 2, 0), (0.5, 2, 1),
                                              (1, 0, 0)])
def test_linear_models_equal_ekf3(gf, alpha, beta, kappa):
    R = np.diag([0.01, 0.02, 0.005])
    ukf = gf.UKF3(MU0, SIGMA0, alpha=alpha, beta=beta, kappa=kappa)
    ekf = gf.EKF3(MU0, SIGMA0)
    motion = gf.EKF3Motion(linear_g, R)
    meas = gf.EKF3Meas(gf.meas_xy, [[0.5, 0.1], [0.1, 0.4]])
    rng = np.random.default_rng(1)
    for _ in range(10):
        u = rng.normal(size=2) * 0.1
        ukf.predict(motion, u)
        ekf.predict(motion, u)
        z = rng.normal(size=2)
        ukf.update(meas, z)
        ekf.update(meas, z)
        assert close(ukf.mu, ekf.mu, UKF_TOL[gf])
        assert close(ukf.sigma, ekf.sigma, UKF_TOL[gf])
        assert ukf.nis == pytest.approx(ekf.nis, rel=UKF_TOL[gf] * 10,
                                        abs=UKF_TOL[gf])


@pytest.mark.parametrize("alpha,beta,kappa", [(1, 2, 0), (0.5, 2, 1)])
def test_nonlinear_beside_table_3_4(alpha, beta, kappa):
    gf = float64
    R = np.diag([0.01, 0.02, 0.005])
    Q = np.array([[0.3, 0.05], [0.05, 0.2]])
    ukf = gf.UKF3(MU0, SIGMA0, alpha=alpha, beta=beta, kappa=kappa)
    ref = Reference(MU0, SIGMA0, alpha, beta, kappa)
    motion = gf.EKF3Motion(gf.forward_turn, R)
    meas = gf.EKF3Meas(mixed_h, Q)
    rng = np.random.default_rng(2)
    for k in range(8):
        u = [0.3, 0.1 * rng.normal()]
        ukf.predict(motion, u)
        ref.predict(turn_g, u, R)
        assert close(ukf.mu, ref.mu, 1e-9) and close(ukf.sigma, ref.P, 1e-9)
        z = mixed_h(ref.mu)[0] + rng.normal(size=2) * 0.3
        ukf.update(meas, z)
        ref.update(mixed_h, z, Q)
        assert close(ukf.mu, ref.mu, 1e-9), (k, ukf.mu, ref.mu)
        assert close(ukf.sigma, ref.P, 1e-9), k


@pytest.mark.parametrize("gf", MODS)
def test_python_h_gives_the_builtins_bits(gf):
    def h_xy(mu):
        return mu[:2].copy(), np.eye(2, 3)
    a, b = gf.UKF3(MU0, SIGMA0), gf.UKF3(MU0, SIGMA0)
    motion = gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01)
    for z in ([1, 0.5], [1.2, 0.9], [1.5, 1.1]):
        a.predict(motion, [0.4, 0.2])
        b.predict(motion, [0.4, 0.2])
        a.update(gf.EKF3Meas(gf.meas_xy, np.eye(2)), z)
        b.update(gf.EKF3Meas(h_xy, np.eye(2)), z)
        assert a.__getstate__() == b.__getstate__()


@pytest.mark.parametrize("gf", MODS)
@pytest.mark.parametrize("python", [False, True])
def test_run_equals_the_calls(gf, python):
    motion = gf.EKF3Motion(turn_g if python else gf.forward_turn,
                           np.eye(3) * 0.01)
    meas = gf.EKF3Meas(gf.meas_xy, np.eye(2) * 0.5, gate=9.0)
    rng = np.random.default_rng(4)
    u = np.column_stack([np.full(12, 0.5), rng.normal(size=12) * 0.2])
    z = rng.normal(size=(12, 2)) + 1
    z[3] = np.nan
    z[7] = [40, 40]  # gated
    a, b = gf.UKF3(MU0, SIGMA0), gf.UKF3(MU0, SIGMA0)
    mu, sigma, nis, status = a.run(motion, meas, u=u, z=z)
    for k in range(12):
        b.predict(motion, u[k])
        if not np.isnan(z[k, 0]):
            try:
                b.update(meas, z[k])
            except gaussfilt.Gated:
                pass
        assert np.array_equal(mu[k], b.mu) and np.array_equal(sigma[k],
                                                               b.sigma)
    assert list(status[6:8]) == [0, -5] and np.isnan(nis[3])
    assert a.__getstate__() == b.__getstate__()
    before = a.__getstate__()
    bad = z.copy()
    bad[5] = [np.inf, 0]
    with pytest.raises(gaussfilt.NonFinite) as e:
        a.run(motion, meas, u=u, z=bad)
    assert e.value.step == 5 and a.__getstate__() == before


@pytest.mark.parametrize("gf", MODS)
def test_bad_input_changes_nothing(gf):
    for kw, exc in (({"alpha": 2.0}, gaussfilt.BadArgument),
                    ({"alpha": gf.UKF3_ALPHA_MIN / 2}, gaussfilt.BadArgument),
                    ({"beta": -1.0}, gaussfilt.BadArgument),
                    ({"kappa": "1"}, gaussfilt.BadArgument),
                    ({"sigma": -np.eye(3)}, gaussfilt.NotPSD),
                    ({"mu": [0, 0, np.nan]}, gaussfilt.NonFinite),
                    ({"mu": [0, 0]}, gaussfilt.BadArgument)):
        args = {"mu": MU0, "sigma": SIGMA0, **kw}
        with pytest.raises(exc):
            gf.UKF3(**args)
    f = gf.UKF3(MU0, SIGMA0)
    motion = gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01)
    meas = gf.EKF3Meas(gf.meas_xy, np.eye(2))
    f.update(meas, [0.4, -0.2])
    before = f.__getstate__()
    last = f.S, f.K, f.loglik

    def raising(mu, u):
        raise KeyError("g")
    for call in (lambda: f.predict(motion, [1.0]),
                 lambda: f.predict(motion, [np.nan, 0]),
                 lambda: f.predict(gf.KF2Model(np.eye(2), np.eye(2))),
                 lambda: f.update(meas, [1, 2, 3]),
                 lambda: f.update(meas, "1"),
                 lambda: f.update(meas, [np.inf, 0]),
                 lambda: f.update(gf.EKF3Meas(gf.meas_xy, np.eye(2), gate=1),
                                  [50, 50]),
                 lambda: f.predict(gf.EKF3Motion(raising, np.eye(3))),
                 lambda: f.reset(MU0, -np.eye(3)),
                 lambda: setattr(f, "sigma", [[1, 2, 0], [2, 1, 0],
                                              [0, 0, 1]]),
                 lambda: setattr(f, "mu", [0, np.nan, 0])):
        with pytest.raises((gaussfilt.GaussfiltError, KeyError)):
            call()
        assert f.__getstate__() == before
        # the last accepted update's S, K and loglik kept, every bit
        assert np.array_equal(f.S, last[0]) and np.array_equal(f.K, last[1])
        assert f.loglik == last[2]


@pytest.mark.parametrize("gf", MODS)
def test_state_setters_and_repr(gf):
    f = gf.UKF3(MU0, SIGMA0, alpha=0.5, beta=2.0, kappa=1.0)
    f.predict(gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01), [1, 0.2])
    f.update(gf.EKF3Meas(gf.meas_x, [[0.5]]), [1.4])
    for make in (lambda x: pickle.loads(pickle.dumps(x)), copy.copy,
                 copy.deepcopy):
        twin = make(f)
        assert twin.__getstate__() == f.__getstate__()
        assert twin.nis == f.nis
        for g in (f, twin):  # the copy steps as the original
            g.predict(gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01),
                      [0.5, 0.1])
        assert twin.__getstate__() == f.__getstate__()
    st = f.__getstate__()
    other = gf.UKF3(MU0, SIGMA0)
    for bad in (st[:2] + (bytes(len(st[2])),) + st[3:],
                st[:2] + (st[2][:-1],) + st[3:],
                float64.KF2([0, 0], np.eye(2)).__getstate__()):
        before = other.__getstate__()
        with pytest.raises(gaussfilt.BadArgument):
            other.__setstate__(bad)
        assert other.__getstate__() == before
    # setters: the weights kept (the scaling is the constructor's)
    f.mu = [1, 2, 3 * math.pi]
    assert f.mu[2] == pytest.approx(math.pi, abs=1e-6)
    f.sigma = np.eye(3) * 0.5
    assert np.array_equal(f.sigma, np.eye(3) * 0.5)
    g = gf.UKF3(f.mu, np.eye(3) * 0.5, alpha=0.5, beta=2.0, kappa=1.0)
    assert g.__getstate__()[2] == f.__getstate__()[2]
    f.reset([0, 0, 0], np.eye(3))
    assert math.isnan(f.nis) and f.innovation is None
    assert repr(f) == "<gaussfilt.%s.UKF3 n=3 mu=[0. 0. 0.]>" % gf.__name__[
        len("gaussfilt."):]
