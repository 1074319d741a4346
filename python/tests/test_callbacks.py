# SPDX-License-Identifier: MIT
"""Python callables as EKF3's models, beside the built-in C models.

- Where the arithmetic is the same, the same bits: a Python g that gets
  sin and cos of the heading from the library (gf_sincos, through
  forward_turn) and does the rest of forward_turn operation for operation
  in the module's precision, and Python h equal to meas_x and meas_xy,
  give every belief, NIS and innovation (gated ones included) of a seeded
  run byte for byte as the C models do.
- Where it is not (g with libm's sin and cos, in double, rounded to the
  module's precision once), within a stated tolerance: each prediction,
  from the same belief, within 4 ulp relative to max(1, |value|) (4 eps:
  8.9e-16 in float64, 4.8e-7 in float32; seen: 1 ulp).
- An exception raised in g or h, at any step, comes out of predict or
  update as that object, the belief as before; the filter then goes on as
  one that never saw the failing step.
"""
import math

import numpy as np
import pytest

from gaussfilt import float32, float64

MODS = [pytest.param(float64, id="float64"), pytest.param(float32, id="float32")]
TOL = {m: 4 * float(np.finfo(m.dtype).eps) for m in (float64, float32)}
STEPS = 60


def g_same(mod):
    """forward_turn in Python: sin and cos of theta from the library's
    gf_sincos (forward_turn at d = 1, phi = 0 has G[0, 2] = -sin, G[1, 2] =
    cos, exactly), the rest as src/ekf3.c computes it, in mod's
    precision."""
    dt = mod.dtype

    def g(mu, u):
        assert mu.dtype == dt and u.dtype == dt
        _, G1 = mod.forward_turn(mu, np.array([1, 0], dt))
        s, c = -G1[0, 2], G1[1, 2]
        d, phi, th = u[0], u[1], mu[2]
        mu_bar = np.array([mu[0] + d * c, mu[1] + d * s, th + phi], dt)
        G = np.eye(3, dtype=dt)
        G[0, 2] = -d * s
        G[1, 2] = d * c
        return mu_bar, G
    return g


def g_libm(mu, u):
    """forward_turn with libm's sin and cos, in double."""
    d, phi, th = float(u[0]), float(u[1]), float(mu[2])
    s, c = math.sin(th), math.cos(th)
    G = np.eye(3)
    G[0, 2], G[1, 2] = -d * s, d * c
    return [float(mu[0]) + d * c, float(mu[1]) + d * s, th + phi], G


def h_x(mu):
    return mu[:1].copy(), [[1, 0, 0]]


def h_xy(mu):
    return mu[:2].copy(), [[1, 0, 0], [0, 1, 0]]


def scenario(seed):
    """(u, which measurement or None, z, gate) per step: moves and turns,
    x or (x, y) readings, some far off behind a gate."""
    rng = np.random.default_rng(seed)
    steps = []
    for k in range(STEPS):
        u = np.array([rng.uniform(0, 1), rng.uniform(-0.6, 0.6)])
        m = int(rng.integers(0, 3))  # 0: no reading
        z = rng.normal(size=m) * 0.5 + (25.0 if rng.random() < 0.1 else 0.0)
        steps.append((u, m, z, 9.0 if rng.random() < 0.5 else 0.0))
    return steps


def run(mod, g, h1, h2, seed):
    """The records of a run: per step (mu, sigma) after the prediction
    and (status, mu, sigma, nis, innovation) after the update, as bytes."""
    ekf = mod.EKF3([0.5, -0.3, 2.9], np.diag([0.2, 0.3, 0.5]))
    R = np.diag([0.01, 0.02, 0.005])
    motion = mod.EKF3Motion(g, R)
    meas = {}
    out = []
    for u, m, z, gate in scenario(seed):
        ekf.predict(motion, u)
        out.append((ekf.mu.tobytes(), ekf.sigma.tobytes()))
        if not m:
            continue
        key = (m, gate)
        if key not in meas:
            Q = [[0.04]] if m == 1 else [[0.04, 0.01], [0.01, 0.05]]
            meas[key] = mod.EKF3Meas(h1 if m == 1 else h2, Q, gate=gate)
        try:
            ekf.update(meas[key], z)
            st, nis, y = 0, ekf.nis, ekf.innovation
        except mod.Gated as e:
            st, nis, y = e.status, e.nis, e.innovation
        out.append((st, ekf.mu.tobytes(), ekf.sigma.tobytes(),
                    np.asarray(nis, mod.dtype).tobytes(), y.tobytes()))
    return out


@pytest.mark.parametrize("mod", MODS)
def test_the_python_models_alone_equal_the_builtins(mod):
    rng = np.random.default_rng(7)
    g = g_same(mod)
    for _ in range(200):
        mu = (rng.normal(size=3) * [10, 10, 4]).astype(mod.dtype)
        u = (rng.normal(size=2) * [3, 1]).astype(mod.dtype)
        for a, b in zip(g(mu, u), mod.forward_turn(mu, u)):
            assert np.asarray(a).tobytes() == b.tobytes()
        for hp, hc in ((h_x, mod.meas_x), (h_xy, mod.meas_xy)):
            for a, b in zip(hp(mu), hc(mu)):
                assert np.asarray(a, mod.dtype).tobytes() == b.tobytes()


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_same_arithmetic_same_bits(mod, seed):
    c = run(mod, mod.forward_turn, mod.meas_x, mod.meas_xy, seed)
    p = run(mod, g_same(mod), h_x, h_xy, seed)
    assert len(c) == len(p)
    for k, (a, b) in enumerate(zip(c, p)):
        assert a == b, "record %d differs" % k
    updates = [r for r in c if len(r) == 5]
    assert any(r[0] == -5 for r in updates) and any(r[0] == 0 for r in updates)


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_libm_sin_and_cos_within_tolerance(mod, seed):
    """Each prediction of a seeded run, from the same belief, with g_libm
    and with forward_turn: within TOL. (Over a whole run the two drift
    apart as far as the filter amplifies a rounding: seen up to 7e-3 in
    float32 after 60 steps; so the steps are compared one at a time.)"""
    ekf = mod.EKF3([0.5, -0.3, 2.9], np.diag([0.2, 0.3, 0.5]))
    R = np.diag([0.01, 0.02, 0.005])
    c_motion = mod.EKF3Motion(mod.forward_turn, R)
    p_motion = mod.EKF3Motion(g_libm, R)
    meas = {1: mod.EKF3Meas(mod.meas_x, [[0.04]]),
            2: mod.EKF3Meas(mod.meas_xy, [[0.04, 0.01], [0.01, 0.05]])}
    worst, differ = 0.0, 0
    for u, m, z, _ in scenario(seed):
        a = mod.EKF3(ekf.mu, ekf.sigma)
        b = mod.EKF3(ekf.mu, ekf.sigma)
        a.predict(c_motion, u)
        b.predict(p_motion, u)
        for x, y in ((a.mu, b.mu), (a.sigma, b.sigma)):
            differ += x.tobytes() != y.tobytes()
            x, y = x.astype(float), y.astype(float)
            worst = max(worst, (np.abs(x - y) / np.maximum(1, np.abs(x))).max())
        ekf.predict(c_motion, u)
        if m and np.abs(z).max() < 20:
            ekf.update(meas[m], z)
    assert worst <= TOL[mod], worst
    assert differ > 0, "libm's sin and cos gave gf_sincos's bits every time"


def snapshot(f):
    y = f.innovation
    return (f.mu.tobytes() + f.sigma.tobytes() + np.float64(f.nis).tobytes()
            + (b"none" if y is None else y.tobytes()))


class Boom(Exception):
    pass


class FailsAt:
    """A model that calls `model` but raises Boom on its call number
    `when` (counted from 0)."""

    def __init__(self, model, when):
        self.model, self.when, self.calls, self.raised = model, when, 0, None

    def __call__(self, *args):
        k = self.calls
        self.calls += 1
        if k == self.when:
            self.raised = Boom("call %d" % k)
            raise self.raised
        return self.model(*args)


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("where", ["g", "h"])
@pytest.mark.parametrize("when", [0, 7])
def test_an_exception_in_a_callback_propagates_and_changes_nothing(
        mod, where, when):
    g = FailsAt(g_same(mod), when if where == "g" else -1)
    h = FailsAt(h_xy, when if where == "h" else -1)
    ekf = mod.EKF3([0.5, -0.3, 2.9], np.diag([0.2, 0.3, 0.5]))
    twin = mod.EKF3([0.5, -0.3, 2.9], np.diag([0.2, 0.3, 0.5]))
    motion = mod.EKF3Motion(g, np.diag([0.01, 0.02, 0.005]))
    meas = mod.EKF3Meas(h, [[0.04, 0.01], [0.01, 0.05]])
    twin_motion = mod.EKF3Motion(mod.forward_turn, motion.R)
    twin_meas = mod.EKF3Meas(mod.meas_xy, meas.Q)
    failed = 0
    for u, _, _, _ in scenario(4)[:12]:
        z = np.array([1.0, -1.0]) + u
        for step, twin_step in ((lambda: ekf.predict(motion, u),
                                 lambda: twin.predict(twin_motion, u)),
                                (lambda: ekf.update(meas, z),
                                 lambda: twin.update(twin_meas, z))):
            before = snapshot(ekf)
            try:
                step()
            except Boom as e:
                assert e is (g.raised if where == "g" else h.raised)
                assert snapshot(ekf) == before
                failed += 1
                continue  # the twin skips this step too
            twin_step()
            assert snapshot(ekf) == snapshot(twin)
    assert failed == 1
