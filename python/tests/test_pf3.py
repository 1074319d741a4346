# SPDX-License-Identifier: MIT
"""PF3, the particle filter, bound with EKF3's conventions, in both
precisions: the same seed gives the same particles bit for bit, another
seed others; each step against the formulas written here in numpy over
the filter's own particles (float64 within 1e-12, float32 1e-5, relative
to max(1, |value|)): a noiseless prediction is g applied to each
particle, an update multiplies the weights by exp(-r^T Q^-1 r / 2) and
normalises, resampling copies particle k floor or ceil of n w_k times,
neff, mu (the heading on the circle) and sigma; exercise 4's two modes;
run equal to the calls bit for bit, a failed run changing nothing; bad
input refused with the particles and the generator unchanged; copy
and pickle keep every bit and step on as the original; the repr."""
import copy
import math
import pickle

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [float32, float64]
TOL = {float32: 1e-5, float64: 1e-12}


def close(a, b, tol):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return bool(np.all(np.abs(a - b) <= tol * max(1.0, np.abs(b).max())))


def wrap(a):
    return np.mod(np.asarray(a) + np.pi, 2 * np.pi) - np.pi


def turn_g(mu, u):  # module level: picklable
    d, phi = u
    c, s = math.cos(mu[2]), math.sin(mu[2])
    return (np.array([mu[0] + d * c, mu[1] + d * s, mu[2] + phi]),
            np.eye(3))


@pytest.mark.parametrize("gf", MODS)
def test_seeded(gf):
    sigma = np.diag([0.1, 0.2, 0.05])
    a = gf.PF3([1, 2, 0.5], sigma, 200, seed=11)
    b = gf.PF3([1, 2, 0.5], sigma, 200, seed=11)
    c = gf.PF3([1, 2, 0.5], sigma, 200, seed=12)
    assert a.__getstate__() == b.__getstate__()
    assert not np.array_equal(a.particles, c.particles)
    assert np.all(a.weights == gf.dtype.type(1) / gf.dtype.type(200))
    motion = gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01)
    for f in (a, b):
        f.predict(motion, [0.5, 0.1])
    assert a.__getstate__() == b.__getstate__()
    # the draws are N(mu, sigma): 4000 of them within sampling error
    big = gf.PF3([1, 2, 0.5], sigma, 4000, seed=3)
    p = big.particles.astype(float)
    assert np.all(np.abs(p.mean(0) - [1, 2, 0.5]) < 4 * np.sqrt(
        np.diag(sigma) / 4000))
    assert close(np.cov(p.T), sigma, 0.1)


@pytest.mark.parametrize("gf", MODS)
def test_steps_beside_numpy(gf):
    f = gf.PF3([0.5, -0.2, 2.9], np.diag([0.2, 0.1, 0.3]), 300, seed=5)
    x0 = f.particles.astype(float)
    u = [0.7, 0.2]
    f.predict(gf.EKF3Motion(turn_g, np.zeros((3, 3))), u)
    want = np.array([turn_g(x, u)[0] for x in x0])
    want[:, 2] = wrap(want[:, 2])
    got = f.particles.astype(float)
    d = got - want
    d[:, 2] = wrap(d[:, 2])
    assert close(d, np.zeros_like(d), TOL[gf]) and close(got[:, :2],
                                                         want[:, :2], TOL[gf])
    # update: w * exp(-r^T Q^-1 r / 2), normalised
    Q = np.array([[0.3, 0.1], [0.1, 0.5]])
    z = [0.9, 0.4]
    w0 = f.weights.astype(float)
    f.update(gf.EKF3Meas(gf.meas_xy, Q), z)
    r = np.asarray(z) - got[:, :2]
    w = w0 * np.exp(-0.5 * np.einsum("ki,ij,kj->k", r, np.linalg.inv(Q), r))
    w /= w.sum()
    assert close(f.weights, w, TOL[gf] * 10)
    assert f.neff == pytest.approx(1 / np.sum(w ** 2), rel=TOL[gf] * 10)
    # the estimate: weighted moments, the heading's mean on the circle
    th = math.atan2(w @ np.sin(got[:, 2]), w @ np.cos(got[:, 2]))
    mean = np.array([w @ got[:, 0], w @ got[:, 1], th])
    assert close(f.mu, mean, TOL[gf] * 10)
    e = got - mean
    e[:, 2] = wrap(e[:, 2])
    assert close(f.sigma, (w[:, None] * e).T @ e, TOL[gf] * 100)
    # low-variance resampling: particle k copied floor or ceil of n w_k
    before = [tuple(x) for x in f.particles]
    counts = {}
    f.resample()
    for x in f.particles:
        counts[tuple(x)] = counts.get(tuple(x), 0) + 1
    for k, x in enumerate(before):
        c = counts.get(x, 0)
        assert math.floor(300 * w[k]) - 1 <= c <= math.ceil(300 * w[k]) + 1
    assert np.all(f.weights == f.weights[0])
    assert f.neff == pytest.approx(300, rel=TOL[gf] * 10)


def test_exercise_4_two_modes():
    """Exercise 4: heading unknown, move 1 forward, measure x = 0: two
    clusters of particles, at y = +1 and y = -1, where the mean is near 0."""
    gf = float64
    f = gf.PF3([0, 0, 0], np.diag([0.01, 0.01, 10000.0]), 2000, seed=1)
    f.predict(gf.EKF3Motion(gf.forward_turn, np.eye(3) * 1e-4), [1, 0])
    f.update(gf.EKF3Meas(gf.meas_x, [[0.01]]), [0.0])
    f.resample()
    y = f.particles[:, 1]
    assert abs(np.mean(y > 0.5) - 0.5) < 0.1 and abs(np.mean(y < -0.5)
                                                      - 0.5) < 0.1
    assert abs(f.mu[1]) < 0.2


@pytest.mark.parametrize("gf", MODS)
@pytest.mark.parametrize("python", [False, True])
def test_run_equals_the_calls(gf, python):
    motion = gf.EKF3Motion(turn_g if python else gf.forward_turn,
                           np.eye(3) * 0.01)
    meas = gf.EKF3Meas(gf.meas_xy, np.eye(2) * 0.5, gate=30.0)
    rng = np.random.default_rng(6)
    u = np.column_stack([np.full(10, 0.5), rng.normal(size=10) * 0.2])
    z = rng.normal(size=(10, 2)) * 0.3 + 0.5
    z[2] = np.nan
    z[6] = [80, 80]  # gated
    a = gf.PF3([0, 0, 0.2], np.eye(3) * 0.1, 100, seed=4)
    b = copy.copy(a)
    mu, sigma, neff, status = a.run(motion, meas, u=u, z=z)
    for k in range(10):
        b.predict(motion, u[k])
        if not np.isnan(z[k, 0]):
            try:
                b.update(meas, z[k])
                b.resample()
            except gaussfilt.Gated:
                pass
        assert np.array_equal(mu[k], b.mu) and np.array_equal(sigma[k],
                                                               b.sigma)
        assert neff[k] == b.neff
    assert list(status) == [0] * 6 + [-5] + [0] * 3
    assert a.__getstate__() == b.__getstate__()
    # without resampling, the weights carry on
    c, d = copy.copy(b), copy.copy(b)
    c.run(motion, meas, u=u[:2], z=z[:2], resample=False)
    for k in range(2):
        d.predict(motion, u[k])
        d.update(meas, z[k])
    assert c.__getstate__() == d.__getstate__()
    # a failure part way puts the particles and the generator back
    before = a.__getstate__()
    bad = z.copy()
    bad[4] = [np.inf, 0]
    with pytest.raises(gaussfilt.NonFinite) as e:
        a.run(motion, meas, u=u, z=bad)
    assert e.value.step == 4 and a.__getstate__() == before
    with pytest.raises(gaussfilt.BadArgument, match="u must have shape"):
        a.run(gf.EKF3Motion(gf.forward_turn, np.eye(3)), steps=3)
    assert a.__getstate__() == before


@pytest.mark.parametrize("gf", MODS)
def test_bad_input_changes_nothing(gf):
    for args, exc in ((([0, 0, 0], np.eye(3), 0), gaussfilt.BadArgument),
                      (([0, 0, 0], np.eye(3), -1), gaussfilt.BadArgument),
                      (([0, 0, 0], np.eye(3), 2.5), gaussfilt.BadArgument),
                      (([0, 0, 0], np.eye(3), 10, 2 ** 32),
                       gaussfilt.BadArgument),
                      (([0, 0, 0], -np.eye(3), 10), gaussfilt.NotPSD),
                      (([0, 0, np.nan], np.eye(3), 10), gaussfilt.NonFinite)):
        with pytest.raises(exc):
            gf.PF3(*args)
    f = gf.PF3([0, 0, 0], np.eye(3), 50, seed=2)
    before = f.__getstate__()
    motion = gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01)

    def raising(mu, u):
        raise KeyError("g")
    for call in (lambda: f.predict(motion, [1.0]),
                 lambda: f.predict(motion, [np.inf, 0]),
                 lambda: f.predict(gf.EKF3Motion(raising, np.eye(3))),
                 lambda: f.update(gf.EKF3Meas(gf.meas_x, [[1.0]]), "1"),
                 lambda: f.update(gf.EKF3Meas(gf.meas_x, [[1.0]]), [np.nan]),
                 lambda: f.update(gf.EKF3Meas(gf.meas_x, [[0.0]]), [0.0]),
                 lambda: f.update(gf.EKF3Meas(gf.meas_x, [[1.0]], gate=1),
                                  [1e3]),
                 lambda: f.reset([0, 0, 0], np.eye(3), 0)):
        with pytest.raises((gaussfilt.GaussfiltError, KeyError)):
            call()
        assert f.__getstate__() == before
    blank = gf.PF3.__new__(gf.PF3)
    for call in (lambda: blank.mu, lambda: blank.particles,
                 lambda: blank.resample(), blank.__getstate__,
                 lambda: blank.predict(motion, [1, 0])):
        with pytest.raises(gaussfilt.BadArgument, match="never initialised"):
            call()
    assert repr(blank) == "<gaussfilt.%s.PF3 particles=0>" % gf.__name__[10:]


@pytest.mark.parametrize("gf", MODS)
def test_copy_pickle_repr(gf):
    f = gf.PF3([1, 0, 0.3], np.eye(3) * 0.1, 64, seed=9)
    motion = gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01)
    meas = gf.EKF3Meas(gf.meas_xy, np.eye(2))
    f.predict(motion, [1, 0.1])
    f.update(meas, [2, 0.2])
    for make in (lambda x: pickle.loads(pickle.dumps(x)), copy.copy,
                 copy.deepcopy):
        twin = make(f)
        assert twin.__getstate__() == f.__getstate__()
        for g in (f, twin):  # the generator travels: the same draws follow
            g.predict(motion, [0.5, 0.1])
            g.update(meas, [2.4, 0.3])
            g.resample()
        assert twin.__getstate__() == f.__getstate__()
    st = f.__getstate__()
    x = np.frombuffer(st[2], dtype=gf.dtype).copy()
    nan = x.copy()
    nan[0] = np.nan
    heading = x.copy()
    heading[2] = 4.0
    weight = x.copy()
    weight[3] = -1
    for bad in (st[:2] + (nan.tobytes(),) + st[3:],
                st[:2] + (heading.tobytes(),) + st[3:],
                st[:2] + (weight.tobytes(),) + st[3:],
                st[:2] + (st[2][:-1],) + st[3:],
                st[:2] + (st[2], bytes(len(st[3]))),
                st[:2] + (b"",) + st[3:], (1, "float16") + st[2:]):
        twin = copy.copy(f)
        with pytest.raises(gaussfilt.BadArgument):
            twin.__setstate__(bad)
        assert twin.__getstate__() == st
    r = repr(f)
    assert r.startswith("<gaussfilt.%s.PF3 particles=64 mu=[" %
                        gf.__name__[10:]), r


def bearing_h(x):  # module level: picklable; (range, bearing) to (4, 3)
    dx, dy = 4.0 - x[0], 3.0 - x[1]
    return (np.array([math.hypot(dx, dy), math.atan2(dy, dx) - x[2]]),
            np.zeros((2, 3)))


def pf3_loglik(x, w, z, h, Q, mask):
    """log sum_k (w_k / W) N(z; h(x_k), Q), in numpy."""
    r = np.array([np.asarray(z, float) - h(xk)[0][:len(z)] for xk in x])
    for i in range(len(z)):
        if mask >> i & 1:
            r[:, i] = wrap(r[:, i])
    d2 = np.einsum("ki,ij,kj->k", r, np.linalg.inv(Q), r)
    lw = np.log(w / w.sum()) - 0.5 * d2
    top = lw.max()
    return (top + math.log(np.exp(lw - top).sum()) - 0.5 * (
        len(z) * math.log(2 * math.pi) + math.log(np.linalg.det(Q))))


@pytest.mark.parametrize("gf", MODS)
def test_loglik(gf):
    """loglik: nan before any update, then the particle filter's
    log-likelihood of the last accepted update's z against the numpy
    formula over the particles and weights read before it (built-in and
    Python h, an angle residual wrapped, weights unequal and equal); kept
    by refused updates, failed runs, copy and pickle; a run's the calls';
    cleared by reset."""
    f = gf.PF3([1, 2, 0.5], np.diag([0.3, 0.2, 0.1]), 200, seed=4)
    assert math.isnan(f.loglik)
    motion = gf.EKF3Motion(gf.forward_turn, np.eye(3) * 0.01)
    Qxy = np.array([[0.3, 0.1], [0.1, 0.5]])
    Qrb = np.array([[0.2, 0.0], [0.0, 0.05]])
    cases = [(gf.EKF3Meas(gf.meas_xy, Qxy), lambda x: (x[:2], None), Qxy,
              0, [1.5, 2.2]),
             (gf.EKF3Meas(gf.meas_x, [[0.2]]), lambda x: (x[:1], None),
              np.array([[0.2]]), 0, [1.4]),
             (gf.EKF3Meas(bearing_h, Qrb, angle_mask=2), bearing_h, Qrb, 2,
              [3.3, 3.1])]
    for k in range(9):
        meas, h, Q, mask, z = cases[k % 3]
        f.predict(motion, [0.2, 0.05])
        if k % 2:
            f.resample()  # equal weights: the mean of the likelihoods
        x, w = f.particles.astype(float), f.weights.astype(float)
        f.update(meas, z)
        want = pf3_loglik(x, w, z, h, Q, mask)
        assert type(f.loglik) is float
        assert close(f.loglik, want, TOL[gf]), (k, f.loglik, want)
    # refused: gated, not finite, a wrong shape; the run that fails
    ll = f.loglik
    gated = gf.EKF3Meas(gf.meas_xy, Qxy, gate=1.0)
    for call in (lambda: f.update(gated, [90, 90]),
                 lambda: f.update(cases[0][0], [np.nan, 1]),
                 lambda: f.update(cases[0][0], [1, 2, 3]),
                 lambda: f.run(motion, cases[0][0], u=[[0.1, 0], [0.1, 0]],
                               z=[[1.5, 2.2], [np.inf, 0]])):
        with pytest.raises(gaussfilt.GaussfiltError):
            call()
        assert f.loglik == ll
    for twin in (copy.copy(f), copy.deepcopy(f),
                 pickle.loads(pickle.dumps(f))):
        assert twin.loglik == ll and twin.__getstate__() == f.__getstate__()
    # a state of version 1 (no loglik) still reads, loglik nan
    st = f.__getstate__()
    assert st[0] == 2 and len(st[4]) == 8
    old = type(f).__new__(type(f))
    old.__setstate__((1,) + st[1:4])
    assert math.isnan(old.loglik) and np.array_equal(old.particles,
                                                     f.particles)
    # run leaves its last update's, as the calls do
    a, b = copy.copy(f), copy.copy(f)
    u = [[0.2, 0.05]] * 3
    z = [[1.5, 2.2], [1.6, 2.3], [np.nan, np.nan]]
    a.run(motion, cases[0][0], u=u, z=z)
    for uk, zk in zip(u, z):
        b.predict(motion, uk)
        if not np.isnan(zk[0]):
            b.update(cases[0][0], zk)
            b.resample()
    assert a.__getstate__() == b.__getstate__() and a.loglik == b.loglik
    f.reset([0, 0, 0], np.eye(3), 10)
    assert math.isnan(f.loglik)
