# SPDX-License-Identifier: MIT
"""The book's tables from Python, in both precisions (docs/exercises.md):
Table 1.1 (exercise 1's predictions), Figure 1.2 (their correlations),
Table 2.1 (exercise 2's update) and Table 4.2 (exercise 4's EKF). The
exact values, to 1e-12 (double) and 2e-5 (float) relative to
max(1, |value|), as tests/gf_test.h."""
import math

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

TOL = {float64: 1e-12, float32: 2e-5}
MODS = [pytest.param(float64, id="float64"), pytest.param(float32, id="float32")]

TABLE_1_1 = [((0, 0), ((0, 0), (0, 0))),
             ((0, 0), ((0.25, 0.5), (0.5, 1))),
             ((0, 0), ((2.5, 2), (2, 2))),
             ((0, 0), ((8.75, 4.5), (4.5, 3))),
             ((0, 0), ((21, 8), (8, 4))),
             ((0, 0), ((41.25, 12.5), (12.5, 5)))]


def close(mod, got, want):
    got, want = np.asarray(got, float), np.asarray(want, float)
    assert got.shape == want.shape
    err = np.abs(got - want) / np.maximum(1.0, np.abs(want))
    assert err.max() <= TOL[mod], (got, want)


def car(mod):
    return mod.KF2Model(A=[[1, 1], [0, 1]], R=[[0.25, 0.5], [0.5, 1]])


@pytest.mark.parametrize("mod", MODS)
def test_table_1_1(mod):
    kf = mod.KF2(mu=[0, 0], sigma=np.zeros((2, 2)))
    for t, (mu, sigma) in enumerate(TABLE_1_1):
        if t:
            kf.predict(car(mod))
        close(mod, kf.mu, mu)
        close(mod, kf.sigma, sigma)
        assert kf.mu.dtype == mod.dtype and kf.sigma.dtype == mod.dtype


@pytest.mark.parametrize("mod", MODS)
def test_figure_1_2(mod):
    """rho_t = Sigma_xv / sqrt(Sigma_xx Sigma_vv) from t = 1 to 10, from
    the exact rationals; undefined at t = 0."""
    kf = mod.KF2([0, 0], np.zeros((2, 2)))
    with pytest.raises(gaussfilt.Undefined) as e:
        mod.correlation(kf.sigma)
    assert e.value.status == -6
    xx, xv, vv = 0.0, 0.0, 0.0
    rhos = []
    for t in range(1, 11):
        # Sigma_t = A Sigma A^T + R, exactly (the entries are binary fractions)
        xx, xv, vv = xx + 2 * xv + vv + 0.25, xv + vv + 0.5, vv + 1
        kf.predict(car(mod))
        rho = mod.correlation(kf.sigma)
        close(mod, rho, xv / math.sqrt(xx * vv))
        rhos.append(rho)
    assert rhos[0] == pytest.approx(1.0, abs=TOL[mod])
    assert round(rhos[1], 3) == 0.894 and round(rhos[9], 3) == 0.867
    assert all(a > b for a, b in zip(rhos, rhos[1:]))
    assert rhos[-1] > math.sqrt(3) / 2


@pytest.mark.parametrize("mod", MODS)
def test_table_2_1(mod):
    kf = mod.KF2([0, 0], np.zeros((2, 2)))
    for _ in range(5):
        kf.predict(car(mod))
    kf.update(mod.KF2Meas(C=[[1, 0]], Q=[[10]]), [5])
    k = np.array([41.25, 12.5]) / 51.25
    close(mod, kf.mu, 5 * k)
    close(mod, kf.sigma, [[41.25 * 10 / 51.25, 12.5 * 10 / 51.25],
                            [12.5 * 10 / 51.25, 5 - 12.5 ** 2 / 51.25]])
    close(mod, kf.nis, 25 / 51.25)
    close(mod, kf.innovation, [5])
    # the worked solutions' digits
    assert [round(float(v), 2) for v in kf.mu] == [4.02, 1.22]


@pytest.mark.parametrize("mod", MODS)
def test_table_4_2(mod):
    ekf = mod.EKF3(mu=[0, 0, 0], sigma=np.diag([0.01, 0.01, 10000]))
    close(mod, ekf.sigma, np.diag([0.01, 0.01, 10000]))
    ekf.predict(mod.EKF3Motion(mod.forward_turn, np.zeros((3, 3))), u=[1, 0])
    close(mod, ekf.mu, [1, 0, 0])
    close(mod, ekf.sigma, [[0.01, 0, 0], [0, 10000.01, 10000],
                             [0, 10000, 10000]])
    ekf.update(mod.EKF3Meas(mod.meas_x, Q=[[0.01]]), z=[-0.7])
    close(mod, ekf.mu, [0.15, 0, 0])
    close(mod, ekf.sigma, [[0.005, 0, 0], [0, 10000.01, 10000],
                             [0, 10000, 10000]])


@pytest.mark.parametrize("mod", MODS)
def test_table_4_2_python_callbacks(mod):
    """The same exercise with g and h written in Python: the same numbers
    as the built-in C models."""
    def g(mu, u):
        th = mu[2]
        G = np.eye(3)
        G[0, 2], G[1, 2] = -math.sin(th) * u[0], math.cos(th) * u[0]
        return [mu[0] + u[0] * math.cos(th), mu[1] + u[0] * math.sin(th),
                th + u[1]], G

    def h(mu):
        return [mu[0]], [[1, 0, 0]]

    ekf = mod.EKF3([0, 0, 0], np.diag([0.01, 0.01, 10000]))
    ekf.predict(mod.EKF3Motion(g, np.zeros((3, 3))), [1, 0])
    ekf.update(mod.EKF3Meas(h, [[0.01]]), [-0.7])
    close(mod, ekf.mu, [0.15, 0, 0])
    close(mod, ekf.sigma, [[0.005, 0, 0], [0, 10000.01, 10000],
                             [0, 10000, 10000]])


@pytest.mark.parametrize("mod", MODS)
def test_any_size_filters_on_table_2_1(mod):
    """KF and EKF at n = 2 on exercises 1 and 2."""
    A = np.array([[1.0, 1], [0, 1]])
    kf = mod.KF([0, 0], np.zeros((2, 2)))
    ekf = mod.EKF([0, 0], np.zeros((2, 2)))
    model = mod.KFModel(A, [[0.25, 0.5], [0.5, 1]])
    motion = mod.EKFMotion(lambda mu, u: (A @ mu, A), [[0.25, 0.5], [0.5, 1]])
    for _ in range(5):
        kf.predict(model)
        ekf.predict(motion)
    close(mod, kf.sigma, TABLE_1_1[5][1])
    close(mod, ekf.sigma, TABLE_1_1[5][1])
    kf.update(mod.KFMeas([[1, 0]], [[10]]), [5])
    ekf.update(mod.EKFMeas(lambda mu: ([mu[0]], [[1, 0]]), [[10]], n=2), [5])
    for f in (kf, ekf):
        close(mod, f.mu, 5 * np.array([41.25, 12.5]) / 51.25)
        close(mod, f.nis, 25 / 51.25)
