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


@pytest.mark.parametrize("gf", [float32, float64])
def test_u_where_the_model_has_no_B_is_refused(gf):
    kf2 = gf.KF2(mu=[1, 2], sigma=np.eye(2))
    k = gf.KF(mu=[1, 2, 3], sigma=np.eye(3))
    car = gf.KF2Model(A=[[1, 1], [0, 1]], R=np.eye(2))  # no B
    model = gf.KFModel(A=np.eye(3), R=np.eye(3))
    assert car.B is None and model.B is None
    before = kf2.__getstate__(), k.__getstate__()
    calls = [
        ("KF2.predict: u given, the model has no B",
         lambda: kf2.predict(car, u=[1, 0])),
        ("KF2.run: u given, the model has no B",
         lambda: kf2.run(car, u=np.ones((3, 2)))),
        ("KF2.run: u without model", lambda: kf2.run(u=np.ones((3, 2)))),
        ("KF.predict: u given, the model has no B",
         lambda: k.predict(model, u=[1])),
        ("KF.run: u given, the model has no B",
         lambda: k.run(model, u=np.ones((3, 1)))),
        ("KF.run: u without model", lambda: k.run(u=np.ones((3, 1)))),
    ]
    for msg, call in calls:
        with pytest.raises(gaussfilt.BadArgument) as e:
            call()
        assert str(e.value) == msg
    assert (kf2.__getstate__(), k.__getstate__()) == before
    # with B, the same u moves the mean
    pushed = gf.KF2Model(A=[[1, 1], [0, 1]], R=np.eye(2), B=np.eye(2))
    kf2.predict(pushed, u=[1, 0])
    assert np.array_equal(pushed.B, np.eye(2)) and kf2.mu[0] == 4


@pytest.mark.parametrize("gf", [float32, float64])
def test_a_scalar_is_a_1x1_matrix_everywhere(gf):
    def h(mu):
        return mu * 2, np.array([[2.0]])

    def g(mu, u):
        return mu + 1, np.array([[1.0]])

    def beliefs(vec, mat):
        """A 1-state run with every (1,) vector given as vec(x) and every
        1 x 1 matrix as mat(x) (the values exact in float32)."""
        k = gf.KF(mu=vec(0.5), sigma=mat(2))
        k.predict(gf.KFModel(A=mat(1), R=mat(0.25), B=mat(2), c=vec(0.125)),
                  u=vec(0.375))
        k.update(gf.KFMeas(C=mat(1), Q=mat(4), c=vec(0.25), gate=9),
                 z=vec(1))
        k.mu, k.sigma = vec(0.75), mat(1.5)
        e = gf.EKF(mu=vec(0.5), sigma=mat(2))
        e.predict(gf.EKFMotion(g=g, R=mat(0.5)))
        e.update(gf.EKFMeas(h=h, Q=mat(3), n=1), z=vec(2.5))
        e3 = gf.EKF3(mu=[0, 0, 0], sigma=np.eye(3))
        e3.update(gf.EKF3Meas(h=gf.meas_x, Q=mat(2)), z=vec(0.5))
        k2 = gf.KF2(mu=[0, 0], sigma=np.eye(2))
        k2.update(gf.KF2Meas(C=[1, 0], Q=mat(2), c=vec(0.5)), z=vec(1))
        return [f.__getstate__() for f in (k, e, e3, k2)]

    arrays = beliefs(lambda x: [x], lambda x: [[x]])
    for one in (lambda x: x, lambda x: float(x), np.float64, np.float32,
                np.array):
        assert beliefs(one, one) == arrays


@pytest.mark.parametrize("gf", [float32, float64])
def test_counts_and_numbers_refused_with_their_name(gf):
    kf2 = gf.KF2(mu=[1, 2], sigma=np.eye(2))
    before = kf2.__getstate__()
    cases = [
        ("KF2Meas: gate: not a real number (str)",
         lambda: gf.KF2Meas(C=[1, 0], Q=1, gate="3")),
        ("KFMeas: gate: not a real number (None)",
         lambda: gf.KFMeas(C=[1, 0], Q=1, gate=None)),
        ("EKF3Meas: gate: not a real number (complex)",
         lambda: gf.EKF3Meas(h=gf.meas_x, Q=1, gate=1j)),
        ("EKFMeas: gate: not a real number (numpy.ndarray)",
         lambda: gf.EKFMeas(h=gf.meas_x, Q=1, n=3, gate=np.array([3.0]))),
        ("KF2Meas: gate must be >= 0 (0: no gate), got -1",
         lambda: gf.KF2Meas(C=[1, 0], Q=1, gate=-1)),
        ("EKF3Meas: angle_mask: not an integer (str)",
         lambda: gf.EKF3Meas(h=gf.meas_x, Q=1, angle_mask="1")),
        ("EKF3Meas: angle_mask must be in 0..4294967295",
         lambda: gf.EKF3Meas(h=gf.meas_x, Q=1, angle_mask=-1)),
        ("EKFMeas: n: not an integer (float)",
         lambda: gf.EKFMeas(h=gf.meas_x, Q=1, n=3.0)),
        ("EKFMeas: angle_mask: not an integer (bytes)",
         lambda: gf.EKFMeas(h=gf.meas_x, Q=1, n=3, angle_mask=b"1")),
        ("EKF: angles: not an integer (None)",
         lambda: gf.EKF(mu=[0], sigma=1, angles=None)),
        ("EKF: angles must be in 0..4294967295",
         lambda: gf.EKF(mu=[0], sigma=1, angles=2 ** 40)),
        ("KF2.run: steps: not an integer (str)", lambda: kf2.run(steps="3")),
        ("KF2.run: steps must be in", lambda: kf2.run(steps=-1)),
        ("ellipse: p: not a real number (str)",
         lambda: gf.ellipse(np.eye(2), p="0.5")),
        ("marginal: i: not an integer (str)",
         lambda: gf.marginal(np.eye(3), "0", 1)),
        ("marginal: j: not an integer (float)",
         lambda: gf.marginal(np.eye(3), 0, 1.0)),
    ]
    for msg, call in cases:
        with pytest.raises(gaussfilt.BadArgument) as e:
            call()
        assert str(e.value).startswith(msg), (msg, str(e.value))
    assert kf2.__getstate__() == before
    # what they take: integers of numpy too, and bools as 0 and 1
    assert gf.EKF(mu=[0, 0], sigma=np.eye(2), angles=np.uint8(2)).angles == 2
    assert gf.KF2Meas(C=[1, 0], Q=1, gate=np.float32(4)).gate == 4
    assert gf.marginal(np.eye(3), np.int64(0), True).shape == (2, 2)
    assert kf2.run(steps=np.int32(2))[0].shape == (2, 2)


def test_every_shape_is_printed_as_numpy_prints_it():
    gf = float64
    cases = [  # (call, the array whose shape the message names)
        (lambda a: gf.KF2Meas(C=a, Q=1), np.ones(3)),
        (lambda a: gf.KF2Meas(C=a, Q=1), np.ones((3, 2))),
        (lambda a: gf.KFMeas(C=a, Q=1), np.ones((1, 1, 1))),
        (lambda a: gf.KFMeas(C=a, Q=1), np.ones((3, 2))),
        (lambda a: gf.KFModel(A=a, R=1), np.ones((2, 3))),
        (lambda a: gf.KFModel(A=np.eye(2), R=np.eye(2), B=a), np.ones((3, 1))),
        (lambda a: gf.EKF3Meas(h=gf.meas_x, Q=a), np.ones((4, 4))),
        (lambda a: gf.KF(mu=a, sigma=np.eye(2)), np.ones((2, 2))),
        (lambda a: gf.KF(mu=a, sigma=1), np.ones(13)),
        (lambda a: gf.KF(mu=[0, 0], sigma=a), np.ones(2)),
        (lambda a: gf.KF2(mu=a, sigma=np.eye(2)), np.ones((2, 1))),
        (lambda a: gf.KF2(mu=[0, 0], sigma=np.eye(2)).update(
            gf.KF2Meas(C=[1, 0], Q=1), a), np.ones((1, 1))),
    ]
    for call, a in cases:
        with pytest.raises(gaussfilt.BadArgument) as e:
            call(a)
        assert str(e.value).endswith("got %s" % (a.shape,)), str(e.value)


def fast_forms(gf):
    """The forms of a one-entry z that take the fast path (read without
    making an array), each with its label."""
    return [("an array of the module's type", np.array([0.5], gf.dtype)),
            ("a float64 array", np.array([0.5])),
            ("a float32 array", np.array([0.5], np.float32)),
            ("a list", [0.5]), ("a tuple", (0.5,)), ("a list of ints", [1]),
            ("a list of numpy.float64", [np.float64(0.5)]),
            ("a list of numpy.float32", [np.float32(0.5)]),
            ("a float", 0.5), ("an int", 1), ("a numpy.float64",
                                               np.float64(0.5)),
            ("a numpy.float32", np.float32(0.5)), ("a numpy.int64",
                                                   np.int64(1))]


def peak_of_updates(kf, meas, z, calls=200):
    """The traced heap's peak over calls updates with z, above what it held
    before: the loop's own bytes when z is read in place, more when each
    call makes an array of it."""
    import tracemalloc
    update = kf.update
    for _ in range(10):
        update(meas, z)
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        before, _ = tracemalloc.get_traced_memory()
        for _ in range(calls):
            update(meas, z)
        return tracemalloc.get_traced_memory()[1] - before
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("gf", [float32, float64])
def test_lists_scalars_and_the_other_precision_take_the_fast_path(gf):
    """No array is made of z in any of the fast forms (what made a list 4x
    and a float64 array given to float32 3.4x an array of the module's
    type): each update's traced heap peaks as the module's own array's
    does, where a form numpy must convert (int16, a large int) peaks
    higher, so the check can fail."""
    kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
    meas = gf.KF2Meas(C=[[1, 0]], Q=[[10]])
    own = peak_of_updates(kf, meas, np.array([0.5], gf.dtype))
    for label, z in fast_forms(gf):
        assert peak_of_updates(kf, meas, z) == own, label
    for z in (np.array([1], np.int16), 2 ** 60, [np.longdouble(0.5)]):
        assert peak_of_updates(kf, meas, z) > own, z


@pytest.mark.parametrize("gf", [float32, float64])
def test_fast_forms_round_as_numpy_rounds(gf):
    """Every form gives numpy's cast of its value, bit for bit; an integer
    beyond 2^53 goes to numpy (which rounds it once, where a double on
    the way would round it twice in float32)."""
    for v in (0.1, 1 / 3, 1e-40, 3.4e38 * 0.99, 2 ** 53, 2 ** 60 + 2 ** 36 + 1,
              -(2 ** 62) - 1):
        want = np.array([v, v]).astype(gf.dtype) if isinstance(v, float) \
            else np.array([v, v], np.int64).astype(gf.dtype)
        t = np.float64 if isinstance(v, float) else np.int64
        for form in ([v, v], (v, v), [t(v), t(v)], np.array([v, v], t)):
            kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
            kf.mu = form
            assert kf.mu.tobytes() == want.tobytes(), (v, form)
    # the double rounding the fast path must not do, seen in numpy itself
    v = 2 ** 60 + 2 ** 36 + 1
    assert np.float32(float(v)) != np.float32(np.int64(v))
