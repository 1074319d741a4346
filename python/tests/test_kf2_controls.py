# SPDX-License-Identifier: MIT
"""KF2Model's B of one column (2, 1) or two (2, 2), in both precisions: B
and nu read back; a one-column model steps bit for bit as the library's
2x2 B with a zero second column and u = (u, 0) (predict, and run with u as
(N, 1) or (N,)); u of the wrong size and B of any other shape refused with
BadArgument naming the argument, the belief unchanged; the model pickles
and copies; rts_smooth takes it."""
import copy
import pickle

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [float32, float64]
A = [[1, 0.5], [0, 1]]
R = [[0.01, 0.002], [0.002, 0.04]]


@pytest.mark.parametrize("gf", MODS)
def test_b_and_nu(gf):
    one = gf.KF2Model(A=A, R=R, B=[[0.125], [0.5]])
    assert one.nu == 1 and one.B.shape == (2, 1) and one.B.dtype == gf.dtype
    assert np.array_equal(one.B, [[0.125], [0.5]])
    two = gf.KF2Model(A=A, R=R, B=[[1, 2], [3, 4]])
    assert two.nu == 2 and np.array_equal(two.B, [[1, 2], [3, 4]])
    none = gf.KF2Model(A=A, R=R)
    assert none.nu == 0 and none.B is None


@pytest.mark.parametrize("gf", MODS)
def test_one_column_steps_as_a_zero_second_column(gf):
    rng = np.random.default_rng(5)
    b = rng.normal(size=(2, 1))
    one = gf.KF2Model(A=A, R=R, B=b, c=[0.1, 0])
    two = gf.KF2Model(A=A, R=R, B=np.hstack([b, np.zeros((2, 1))]),
                      c=[0.1, 0])
    meas = gf.KF2Meas(C=[[1, 0]], Q=[[0.5]])
    u = rng.normal(size=20)
    z = rng.normal(size=20)
    a = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    b2 = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    for uk, form in zip(u, [lambda x: x, lambda x: [x], np.atleast_1d,
                            gf.dtype.type] * 5):
        mu0 = a.mu.astype(float)
        a.predict(one, form(uk))
        b2.predict(two, [uk, 0.0])
        assert a.__getstate__() == b2.__getstate__()
        want = np.asarray(A) @ mu0 + np.asarray(b, float)[:, 0] * float(
            gf.dtype.type(uk)) + [0.1, 0]
        assert np.allclose(a.mu, want, rtol=1e-5 if gf is float32 else 1e-14)
    start = a.__getstate__()
    runs = []
    for U in (u.reshape(-1, 1), u):
        a.__setstate__(start)
        runs.append(a.run(one, meas, u=U, z=z))
    b2.__setstate__(start)
    ref = b2.run(two, meas, u=np.column_stack([u, np.zeros_like(u)]), z=z)
    for got in runs:
        for x, y in zip(got, ref):
            assert np.array_equal(x, y)


@pytest.mark.parametrize("gf", MODS)
def test_refused_shapes_name_the_argument(gf):
    for B in ([1, 2], [[1, 2, 3]], np.eye(3), 1.0, np.ones((2, 3)),
              np.ones((2, 1, 1)), [[1], [2], [3]]):
        with pytest.raises(gaussfilt.BadArgument, match="KF2Model: B must"):
            gf.KF2Model(A=A, R=R, B=B)
    for B in ("ab", 1j, [["x"], ["y"]]):
        with pytest.raises(gaussfilt.BadArgument, match="KF2Model: B"):
            gf.KF2Model(A=A, R=R, B=B)
    one = gf.KF2Model(A=A, R=R, B=[[1], [0.5]])
    meas = gf.KF2Meas(C=[[1, 0]], Q=[[1]])
    kf = gf.KF2(mu=[0, 1], sigma=np.eye(2))
    before = kf.__getstate__()
    for u in ([1, 2], np.ones((1, 2)), "1", 1j):
        with pytest.raises(gaussfilt.BadArgument, match="KF2.predict: u"):
            kf.predict(one, u)
    with pytest.raises(gaussfilt.BadArgument,
                       match=r"KF2.run: u must have shape \(steps, 1\)"):
        kf.run(one, meas, u=np.ones((3, 2)), z=np.ones(3))
    two = gf.KF2Model(A=A, R=R, B=np.eye(2))
    with pytest.raises(gaussfilt.BadArgument,
                       match=r"KF2.run: u must have shape \(steps, 2\)"):
        kf.run(two, meas, u=np.ones(3), z=np.ones(3))
    with pytest.raises(gaussfilt.BadArgument, match="KF2.predict: u"):
        kf.predict(two, [1.0])
    assert kf.__getstate__() == before


@pytest.mark.parametrize("gf", MODS)
def test_pickle_copy_and_smooth(gf):
    one = gf.KF2Model(A=A, R=R, B=[[0.25], [1]], c=[0, 0.1])
    for twin in (pickle.loads(pickle.dumps(one)), copy.copy(one),
                 copy.deepcopy(one)):
        assert twin.nu == 1 and np.array_equal(twin.B, one.B)
        a, b = gf.KF2(mu=[0, 0], sigma=np.eye(2)), gf.KF2(mu=[0, 0],
                                                           sigma=np.eye(2))
        a.predict(one, 0.7)
        b.predict(twin, 0.7)
        assert a.__getstate__() == b.__getstate__()
    rng = np.random.default_rng(3)
    u = rng.normal(size=(30, 1))
    meas = gf.KF2Meas(C=[[1, 0]], Q=[[0.5]])
    kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    mu, sigma, _, _ = kf.run(one, meas, u=u, z=rng.normal(size=30))
    ms, ss = gaussfilt.rts_smooth(mu, sigma, one, u=u)
    # the same smoother with the model's B as (2, 2) and u's second column 0
    two = gf.KF2Model(A=A, R=R, B=[[0.25, 0], [1, 0]], c=[0, 0.1])
    ms2, ss2 = gaussfilt.rts_smooth(mu, sigma, two,
                                    u=np.hstack([u, np.zeros_like(u)]))
    assert np.array_equal(ms, ms2) and np.array_equal(ss, ss2)
