# SPDX-License-Identifier: MIT
"""Singular and Undefined raised by the steps themselves, in both
precisions, with the belief (mean, covariance, NIS, innovation) unchanged
byte for byte afterwards.

GF_ERR_SINGULAR comes from an update whose innovation covariance S has a
zero on its diagonal once whitened: a quantity measured without noise
whose predicted variance is zero too. Two cases per filter:

- m = 1: a state known exactly (Sigma = 0) measured with Q = 0, S = 0;
- m = 2: the same state measured twice without noise (Sigma > 0): the
  first copy is taken exactly, which leaves the second a zero predicted
  variance. The library has written part of the new factors when it sees
  that; the belief must still come back as it was.

No step of KF2, EKF3, KF or EKF returns GF_ERR_UNDEFINED from its own
arithmetic (the library's helpers do: `correlation`, test_golden.py). An
EKF's callback may raise it (or any GaussfiltError); the step then raises
that very exception, not ModelError, and leaves the belief unchanged.
"""
import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [pytest.param(float64, id="float64"), pytest.param(float32, id="float32")]


def snapshot(f):
    y = f.innovation
    return (f.mu.tobytes() + f.sigma.tobytes() + np.float64(f.nis).tobytes()
            + (b"none" if y is None else y.tobytes()))


def singular_cases(mod):
    """(name, filter, the update that must raise Singular, an update of
    the same filter that must pass: the neighbour showing what made the
    first fail). Every filter has had one accepted update, so that its
    NIS and innovation are set and can be seen to stay."""
    out = []
    # KF2
    known = mod.KF2([1, 2], np.zeros((2, 2)))
    known.update(mod.KF2Meas([[1, 0]], [[1]]), [1.5])  # S = Q = 1
    out.append(("KF2 m=1", known,
                lambda f: f.update(mod.KF2Meas([[1, 0]], [[0]]), [1]),
                lambda f: f.update(mod.KF2Meas([[1, 0]], [[1e-3]]), [1])))
    kf2 = mod.KF2([1, 2], [[2, 0.5], [0.5, 1]])
    kf2.update(mod.KF2Meas([[1, 0]], [[10]]), [1.5])
    out.append(("KF2 m=2", kf2,
                lambda f: f.update(mod.KF2Meas([[1, 0], [1, 0]],
                                               np.zeros((2, 2))), [1, 1]),
                lambda f: f.update(mod.KF2Meas([[1, 0], [0, 1]],
                                               np.zeros((2, 2))), [1, 1])))
    # EKF3, with the built-in h and with a Python one
    ekf3 = mod.EKF3([1, 2, 0.5], np.zeros((3, 3)))
    ekf3.update(mod.EKF3Meas(mod.meas_x, [[1]]), [1.5])
    out.append(("EKF3 m=1 meas_x", ekf3,
                lambda f: f.update(mod.EKF3Meas(mod.meas_x, [[0]]), [1]),
                lambda f: f.update(mod.EKF3Meas(mod.meas_x, [[1e-3]]), [1])))
    twice = lambda mu: ([mu[0], mu[0]], [[1, 0, 0], [1, 0, 0]])
    ekf3b = mod.EKF3([1, 2, 0.5], np.diag([2.0, 1.0, 0.1]))
    ekf3b.update(mod.EKF3Meas(mod.meas_xy, np.eye(2)), [1.5, 2.5])
    out.append(("EKF3 m=2 Python h", ekf3b,
                lambda f: f.update(mod.EKF3Meas(twice, np.zeros((2, 2))),
                                   [1, 1]),
                lambda f: f.update(mod.EKF3Meas(mod.meas_xy,
                                                np.zeros((2, 2))), [1, 1])))
    # KF at n = 4
    C2 = np.zeros((2, 4))
    C2[:, 0] = 1
    kf = mod.KF(np.arange(4.0), np.zeros((4, 4)))
    kf.update(mod.KFMeas(np.eye(1, 4), [[1]]), [0.5])
    out.append(("KF m=1", kf,
                lambda f: f.update(mod.KFMeas(np.eye(1, 4), [[0]]), [1]),
                lambda f: f.update(mod.KFMeas(np.eye(1, 4), [[1e-3]]), [1])))
    kfb = mod.KF(np.arange(4.0), np.eye(4) + 0.1)
    kfb.update(mod.KFMeas(np.eye(1, 4), [[1]]), [0.5])
    out.append(("KF m=2", kfb,
                lambda f: f.update(mod.KFMeas(C2, np.zeros((2, 2))), [1, 1]),
                lambda f: f.update(mod.KFMeas(np.eye(2, 4), np.zeros((2, 2))),
                                   [1, 1])))
    # EKF at n = 4, its h in Python
    ekf = mod.EKF(np.arange(4.0), np.zeros((4, 4)))
    first = lambda mu: ([mu[0]], np.eye(1, 4))
    ekf.update(mod.EKFMeas(first, [[1]], n=4), [0.5])
    out.append(("EKF m=1", ekf,
                lambda f: f.update(mod.EKFMeas(first, [[0]], n=4), [1]),
                lambda f: f.update(mod.EKFMeas(first, [[1e-3]], n=4), [1])))
    ekfb = mod.EKF(np.arange(4.0), np.eye(4) + 0.1)
    ekfb.update(mod.EKFMeas(first, [[1]], n=4), [0.5])
    out.append(("EKF m=2", ekfb,
                lambda f: f.update(mod.EKFMeas(lambda mu: ([mu[0], mu[0]], C2),
                                               np.zeros((2, 2)), n=4), [1, 1]),
                lambda f: f.update(mod.EKFMeas(
                    lambda mu: (mu[:2], np.eye(2, 4)), np.zeros((2, 2)), n=4),
                    [1, 1])))
    return out


CASE_IDS = ["KF2 m=1", "KF2 m=2", "EKF3 m=1 meas_x", "EKF3 m=2 Python h",
            "KF m=1", "KF m=2", "EKF m=1", "EKF m=2"]


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("case", range(len(CASE_IDS)), ids=CASE_IDS)
def test_update_raises_singular_and_changes_nothing(mod, case):
    name, filt, bad, good = singular_cases(mod)[case]
    assert name == CASE_IDS[case]
    before = snapshot(filt)
    with pytest.raises(gaussfilt.Singular) as e:
        bad(filt)
    assert isinstance(e.value, ArithmeticError)
    assert e.value.status == -4 and e.value.status_name == "GF_ERR_SINGULAR"
    assert e.value.args[0].endswith(
        ".update: singular innovation covariance"), e.value.args
    assert snapshot(filt) == before
    # the same filter, then, takes a measurement it can take, and that
    # one changes the belief
    good(filt)
    assert snapshot(filt) != before


@pytest.mark.parametrize("mod", MODS)
def test_a_run_that_meets_a_singular_update_changes_nothing(mod):
    """KF2.run and KF.run: a step 3 that measures one state twice without
    noise raises Singular with exc.step = 3, the belief as before the
    call."""
    for make, model, meas in [
            (lambda: mod.KF2([1, 2], np.eye(2)),
             mod.KF2Model(np.eye(2), np.zeros((2, 2))),
             mod.KF2Meas([[1, 0], [1, 0]], np.zeros((2, 2)))),
            (lambda: mod.KF(np.ones(3), np.eye(3)),
             mod.KFModel(np.eye(3), np.zeros((3, 3))),
             mod.KFMeas([[1, 0, 0], [1, 0, 0]], np.zeros((2, 2))))]:
        filt = make()
        before = snapshot(filt)
        z = np.full((6, 2), np.nan)
        z[3] = 1
        with pytest.raises(gaussfilt.Singular) as e:
            filt.run(model, meas, z=z)
        assert e.value.step == 3
        assert snapshot(filt) == before
        # the steps before it ran: without step 3 the run goes through
        z[3] = np.nan
        mu = filt.run(model, meas, z=z)[0]
        assert mu.shape[0] == 6


class Raising:
    """A callback that raises `exc` (made fresh per call)."""

    def __init__(self, exc):
        self.exc = exc
        self.raised = []

    def __call__(self, *args):
        e = self.exc()
        self.raised.append(e)
        raise e


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("exc", [gaussfilt.Undefined, gaussfilt.Singular,
                                 gaussfilt.NotPSD])
def test_a_gaussfilt_error_from_a_callback_comes_out_as_itself(mod, exc):
    """An EKF3 or EKF callback raising Undefined (say, a bearing from a
    robot standing on its landmark): predict and update raise that
    exception object, unchanged, and leave the belief as it was."""
    ekf3 = mod.EKF3([1, 2, 0.5], np.diag([2.0, 1.0, 0.1]))
    ekf3.update(mod.EKF3Meas(mod.meas_xy, np.eye(2)), [1.5, 2.5])
    ekf = mod.EKF(np.arange(3.0), np.eye(3))
    ekf.update(mod.EKFMeas(lambda mu: (mu[:2], np.eye(2, 3)), np.eye(2), n=3),
               [0.5, 1.5])
    for filt, step in [
            (ekf3, lambda cb: ekf3.predict(mod.EKF3Motion(cb, np.eye(3)),
                                           [1, 0])),
            (ekf3, lambda cb: ekf3.update(mod.EKF3Meas(cb, [[1]]), [1])),
            (ekf, lambda cb: ekf.predict(mod.EKFMotion(cb, np.eye(3)))),
            (ekf, lambda cb: ekf.update(mod.EKFMeas(cb, [[1]], n=3), [1]))]:
        before = snapshot(filt)
        cb = Raising(exc)
        with pytest.raises(exc) as e:
            step(cb)
        assert len(cb.raised) == 1 and e.value is cb.raised[0]
        assert type(e.value) is exc, "converted to %r" % type(e.value)
        assert snapshot(filt) == before
