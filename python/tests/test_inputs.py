# SPDX-License-Identifier: MIT
"""Inputs at the edges: None, text, bytes, complex numbers and objects are
refused with BadArgument naming the argument, the belief unchanged (not
parsed, not truncated); booleans, integers, numpy scalars and Python
floats are numbers; a scalar stands for a 1 x 1 matrix; shapes are
printed as numpy prints them."""
import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

REFUSED = ["1.5", b"1", None, [1 + 2j], np.array([1], dtype=object),
           np.array(["1"]), [None]]


@pytest.mark.parametrize("gf", [float32, float64])
@pytest.mark.parametrize("bad", REFUSED, ids=repr)
def test_non_numbers_are_refused_everywhere(gf, bad):
    kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    meas = gf.KF2Meas(C=[[1, 0]], Q=[[1]])
    car = gf.KF2Model(A=np.eye(2), R=np.eye(2), B=np.eye(2))
    k = gf.KF(mu=[0, 0, 0], sigma=np.eye(3))
    kmeas = gf.KFMeas(C=[[1, 0, 0]], Q=[[1]])
    before = kf.__getstate__(), k.__getstate__()
    calls = [
        ("KF2.update: z", lambda: kf.update(meas, bad)),
        ("KF2.predict: u", lambda: kf.predict(car, bad)),
        ("KF.update: z", lambda: k.update(kmeas, bad)),
        ("KF2.run: z", lambda: kf.run(meas=meas, z=bad)),
        ("KF: mu", lambda: gf.KF(mu=bad, sigma=np.eye(1))),
        ("KF2Meas", lambda: gf.KF2Meas(C=[[1, 0]], Q=bad)),
    ]
    for who, call in calls:
        if bad is None and who in ("KF2.predict: u", "KF2.run: z"):
            continue  # None is "not given" there: no control, no z
        with pytest.raises(gaussfilt.BadArgument) as e:
            call()
        assert who in str(e.value), (who, str(e.value))
    assert (kf.__getstate__(), k.__getstate__()) == before


@pytest.mark.parametrize("gf", [float32, float64])
def test_numbers_of_every_kind(gf):
    meas = gf.KF2Meas(C=[[1, 0]], Q=2)  # a scalar for the 1 x 1 Q
    assert np.array_equal(meas.Q, [[2]])
    results = []
    for z in (1.5, 1.5, [1.5], np.float32(1.5), np.array([1.5]), [3 / 2]):
        kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
        kf.update(meas, z)
        results.append(kf.__getstate__())
    assert all(r == results[0] for r in results)
    kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    kf.update(meas, [True])  # a boolean is 1
    kf2 = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    kf2.update(meas, 1)
    assert kf.__getstate__() == kf2.__getstate__()


def test_shapes_are_printed_as_numpy_prints_them():
    gf = float64
    with pytest.raises(gaussfilt.BadArgument, match=r"got \(1, 2\)"):
        gf.KF2Meas(C=[[1, 0]], Q=[[1, 2]])
    with pytest.raises(gaussfilt.BadArgument, match=r"got \(3,\)"):
        gf.KF2(mu=[0, 0, 0], sigma=np.eye(2))
    with pytest.raises(gaussfilt.BadArgument, match=r"got \(2, 2\)"):
        gf.KF(mu=[0], sigma=np.eye(2))
