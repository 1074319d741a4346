# SPDX-License-Identifier: MIT
"""Bad input: wrong shapes, NaN, non-PSD matrices and callbacks that raise
each get a clear exception, and leave the belief exactly as it was; 10^5
failing calls neither crash nor leak (tracemalloc and the RSS)."""
import gc
import tracemalloc

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [pytest.param(float64, id="float64"), pytest.param(float32, id="float32")]


def snapshot(f):
    return f.mu.tobytes() + f.sigma.tobytes() + np.float64(f.nis).tobytes()


def filters(mod):
    """One of each filter, a step taken, with a good model and a
    measurement, and the (exception, call) pairs that must fail."""
    out = {}
    kf2 = mod.KF2([1, 2], [[2, 0.5], [0.5, 1]])
    m2 = mod.KF2Model([[1, 1], [0, 1]], [[0.25, 0.5], [0.5, 1]])
    q2 = mod.KF2Meas([[1, 0]], [[10]])
    b2 = mod.KF2Model([[1, 1], [0, 1]], np.eye(2), B=np.eye(2))
    kf2.predict(m2)
    kf2.update(q2, [1.5])
    out["KF2"] = (kf2, [
        (gaussfilt.BadArgument, lambda: kf2.update(q2, [1, 2])),
        (gaussfilt.BadArgument, lambda: kf2.update(q2, "five")),
        (gaussfilt.BadArgument, lambda: kf2.predict(b2, [1, 2, 3])),
        (gaussfilt.BadArgument, lambda: kf2.predict(m2, [1, 0])),  # no B
        (gaussfilt.BadArgument, lambda: kf2.predict(q2)),
        (gaussfilt.BadArgument, lambda: mod.KF2Model(np.eye(3), np.eye(2))),
        (gaussfilt.NonFinite, lambda: kf2.update(q2, [np.nan])),
        (gaussfilt.NonFinite, lambda: kf2.predict(b2, [np.inf, 0])),
        (gaussfilt.NonFinite, lambda: mod.KF2Model([[np.nan, 0], [0, 1]],
                                                   np.eye(2))),
        (gaussfilt.NotPSD, lambda: mod.KF2Model(np.eye(2), [[1, 2], [2, 1]])),
        (gaussfilt.NotPSD, lambda: mod.KF2Meas([[1, 0]], [[-1]])),
        (gaussfilt.NotPSD, lambda: kf2.__init__([0, 0], [[1, 0], [1, 1]])),
        (gaussfilt.Gated, lambda: kf2.update(mod.KF2Meas([[1, 0]], [[1]],
                                                         gate=1), [1e3])),
    ])
    ekf3 = mod.EKF3([0, 0, 0.5], np.eye(3))
    mo3 = mod.EKF3Motion(mod.forward_turn, np.eye(3) * 0.01)
    me3 = mod.EKF3Meas(mod.meas_xy, np.eye(2))
    ekf3.predict(mo3, [1, 0.1])

    def boom(*a):
        raise KeyError("the model failed")
    out["EKF3"] = (ekf3, [
        (KeyError, lambda: ekf3.predict(mod.EKF3Motion(boom, np.eye(3)), [1])),
        (KeyError, lambda: ekf3.update(mod.EKF3Meas(boom, [[1]]), [1])),
        (gaussfilt.BadArgument, lambda: ekf3.predict(mo3, [1])),
        (gaussfilt.BadArgument, lambda: ekf3.update(me3, [1, 2, 3])),
        (gaussfilt.BadArgument, lambda: ekf3.predict(
            mod.EKF3Motion(lambda mu, u: (mu[:2], np.eye(3)), np.eye(3)))),
        (gaussfilt.BadArgument, lambda: ekf3.update(
            mod.EKF3Meas(lambda mu: None, [[1]]), [1])),
        (gaussfilt.BadArgument, lambda: mod.EKF3Meas(mod.meas_x, np.eye(2))),
        (gaussfilt.NonFinite, lambda: ekf3.predict(
            mod.EKF3Motion(lambda mu, u: (mu * np.nan, np.eye(3)),
                           np.eye(3)))),
        (gaussfilt.NonFinite, lambda: ekf3.update(me3, [np.nan, 1])),
        (gaussfilt.NotPSD, lambda: mod.EKF3Motion(mod.forward_turn,
                                                  -np.eye(3))),
    ])
    kf = mod.KF(np.zeros(4), np.eye(4))
    mk = mod.KFModel(np.eye(4), np.eye(4) * 0.1, B=np.ones((4, 1)))
    qk = mod.KFMeas(np.eye(2, 4), np.eye(2))
    kf.predict(mk, [0.5])
    kf.update(qk, [0.1, 0.2])
    out["KF"] = (kf, [
        (gaussfilt.BadArgument, lambda: kf.update(qk, [1])),
        (gaussfilt.BadArgument, lambda: kf.predict(mk, [1, 2])),
        (gaussfilt.BadArgument, lambda: kf.predict(
            mod.KFModel(np.eye(3), np.eye(3)))),
        (gaussfilt.BadArgument, lambda: mod.KFModel(np.eye(4), np.eye(3))),
        (gaussfilt.BadArgument, lambda: mod.KFModel(np.eye(13), np.eye(13))),
        (gaussfilt.NonFinite, lambda: kf.update(qk, [np.nan, 0])),
        (gaussfilt.NotPSD, lambda: mod.KFMeas(np.eye(2, 4),
                                              [[1, 0], [0, -1]])),
        (gaussfilt.NotPSD, lambda: kf.__init__(np.zeros(4), -np.eye(4))),
    ])
    ekf = mod.EKF(np.zeros(4), np.eye(4))
    mh = mod.EKFMeas(lambda mu: (mu[:2], np.eye(2, 4)), np.eye(2), n=4)
    ekf.update(mh, [0.3, 0.1])
    out["EKF"] = (ekf, [
        (ZeroDivisionError, lambda: ekf.predict(
            mod.EKFMotion(lambda mu, u: 1 / 0, np.eye(4)))),
        (KeyError, lambda: ekf.update(mod.EKFMeas(boom, [[1]], n=4), [1])),
        (gaussfilt.BadArgument, lambda: ekf.update(
            mod.EKFMeas(lambda mu: (mu[:2], np.eye(2)), np.eye(2), n=4),
            [0, 0])),
        (gaussfilt.BadArgument, lambda: ekf.update(mh, [0, 0, 0])),
        (gaussfilt.NonFinite, lambda: ekf.update(
            mod.EKFMeas(lambda mu: ([np.inf, 0], np.eye(2, 4)), np.eye(2),
                        n=4), [0, 0])),
        (gaussfilt.NotPSD, lambda: mod.EKFMotion(lambda mu, u: None,
                                                 [[1, 2], [2, 1]])),
    ])
    return out


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("name", ["KF2", "EKF3", "KF", "EKF"])
def test_each_bad_input_raises_and_changes_nothing(mod, name):
    filt, cases = filters(mod)[name]
    before = snapshot(filt)
    for exc, call in cases:
        with pytest.raises(exc) as e:
            call()
        assert str(e.value), "an exception with no message"
        if isinstance(e.value, gaussfilt.GaussfiltError):
            assert e.value.status < 0
            assert type(e.value).status == e.value.status
        assert snapshot(filt) == before, "belief changed by %r" % e.value


@pytest.mark.parametrize("mod", MODS)
def test_messages_name_the_argument_and_the_shapes(mod):
    kf = mod.KF2([0, 0], np.eye(2))
    with pytest.raises(gaussfilt.BadArgument,
                       match=r"KF2.update: z must have shape \(1,\), got \(3,\)"):
        kf.update(mod.KF2Meas([[1, 0]], [[1]]), [1, 2, 3])
    with pytest.raises(ValueError, match=r"KFModel: R must have shape \(3, 3\)"):
        mod.KFModel(np.eye(3), np.eye(2))
    with pytest.raises(gaussfilt.NotPSD, match="KF2Model: covariance not "
                       "positive semidefinite"):
        mod.KF2Model(np.eye(2), [[1, 2], [2, 1]])


@pytest.mark.parametrize("mod", MODS)
def test_gated_carries_the_innovation_and_nis(mod):
    kf = mod.KF2([0, 0], np.eye(2))
    with pytest.raises(gaussfilt.Gated) as e:
        kf.update(mod.KF2Meas([[1, 0]], [[1]], gate=9), [10])
    assert e.value.status == -5 and e.value.status_name == "GF_ERR_GATED"
    np.testing.assert_array_equal(e.value.innovation, [10])
    assert e.value.nis == pytest.approx(50, rel=1e-6)  # 10^2 / (1 + 1)
    assert np.isnan(kf.nis) and kf.innovation is None


def reentry_setup(mod, family):
    """A filter of `family`, a motion and a measurement for it, and a
    function making a motion (or measurement) whose callback first runs
    `inner` (on the filter) and then computes the model."""
    if family == "EKF3":
        filt = mod.EKF3([1, 2, 0.5], np.diag([2.0, 1.0, 0.1]))
        motion = mod.EKF3Motion(mod.forward_turn, np.eye(3) * 0.01)
        meas = mod.EKF3Meas(mod.meas_x, [[1]])
        u = [1.0, 0.1]

        def with_g(inner):
            def g(mu, u):
                inner()
                return mod.forward_turn(mu, u)
            return mod.EKF3Motion(g, np.eye(3) * 0.01)

        def with_h(inner):
            def h(mu):
                inner()
                return mod.meas_x(mu)
            return mod.EKF3Meas(h, [[1]])
        reinit = lambda: filt.__init__([0, 0, 0], np.eye(3))
    else:
        A = np.eye(4) + 0.1 * np.eye(4, k=1)
        filt = mod.EKF(np.arange(4.0), np.eye(4))
        motion = mod.EKFMotion(lambda mu, u: (A @ mu, A), np.eye(4) * 0.01)
        meas = mod.EKFMeas(lambda mu: (mu[:1], np.eye(1, 4)), [[1]], n=4)
        u = None

        def with_g(inner):
            def g(mu, u):
                inner()
                return A @ mu, A
            return mod.EKFMotion(g, np.eye(4) * 0.01)

        def with_h(inner):
            def h(mu):
                inner()
                return mu[:1], np.eye(1, 4)
            return mod.EKFMeas(h, [[1]], n=4)
        reinit = lambda: filt.__init__(np.zeros(4), np.eye(4))
    filt.predict(motion, u)
    filt.update(meas, [1.5])
    inners = {"update": lambda: filt.update(meas, [1]),
              "predict": lambda: filt.predict(motion, u),
              "__init__": reinit}
    return filt, motion, meas, u, with_g, with_h, inners


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("family", ["EKF3", "EKF"])
@pytest.mark.parametrize("inner", ["update", "predict", "__init__"])
@pytest.mark.parametrize("where", ["g", "h"])
def test_a_callback_may_not_step_its_own_filter(mod, family, inner, where):
    """A callback that calls predict, update or __init__ on the filter
    whose step is running gets RuntimeError (the guard against the
    library's belief being written twice); the step raises it, the belief
    is unchanged, and the filter steps as before afterwards."""
    filt, motion, meas, u, with_g, with_h, inners = reentry_setup(mod, family)
    twin = reentry_setup(mod, family)[0]
    calls = []

    def nested():
        calls.append(inner)
        inners[inner]()
    before = snapshot(filt)
    assert snapshot(twin) == before
    with pytest.raises(RuntimeError, match="own callback"):
        if where == "g":
            filt.predict(with_g(nested), u)
        else:
            filt.update(with_h(nested), [1])
    assert calls == [inner]
    assert snapshot(filt) == before
    # not left busy: the next steps are the twin's, bit for bit
    for f in (filt, twin):
        f.predict(motion, u)
        f.update(meas, [0.5])
    assert snapshot(filt) == snapshot(twin)


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("family", ["EKF3", "EKF"])
def test_a_callback_may_step_another_filter(mod, family):
    """The guard is per filter: a callback stepping another filter of the
    same kind (with the same models) works, and both filters end as
    they would have stepped one after the other."""
    filt, motion, meas, u, with_g, with_h, _ = reentry_setup(mod, family)
    other, twin, twin_other = (reentry_setup(mod, family)[0]
                               for _ in range(3))
    filt.predict(with_g(lambda: other.predict(motion, u)), u)
    filt.update(with_h(lambda: other.update(meas, [0.5])), [1])
    twin_other.predict(motion, u)
    twin_other.update(meas, [0.5])
    twin.predict(motion, u)
    twin.update(meas, [1])
    assert snapshot(filt) == snapshot(twin)
    assert snapshot(other) == snapshot(twin_other)
    assert snapshot(filt) != snapshot(other)


def rss_kib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS")


def failing_calls(mod, count):
    filt, cases = filters(mod)["EKF3"]
    _, cases2 = filters(mod)["KF2"]
    cases = cases + cases2
    for k in range(count):
        exc, call = cases[k % len(cases)]
        try:
            call()
        except exc:
            pass
        else:
            raise AssertionError("call %d did not fail" % k)


@pytest.mark.parametrize("mod", MODS)
def test_no_leak_over_100000_failing_calls(mod):
    failing_calls(mod, 5000)  # warm up: caches, interned strings
    gc.collect()
    rss0 = rss_kib()
    tracemalloc.start()
    snap0 = tracemalloc.take_snapshot()
    failing_calls(mod, 100000)
    gc.collect()
    snap1 = tracemalloc.take_snapshot()
    tracemalloc.stop()
    grown = sum(s.size_diff for s in snap1.compare_to(snap0, "filename"))
    rss1 = rss_kib()
    assert grown < 64 * 1024, "Python heap grew by %d bytes" % grown
    assert rss1 - rss0 < 2048, "RSS grew by %d KiB" % (rss1 - rss0)
