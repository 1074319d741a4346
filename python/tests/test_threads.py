# SPDX-License-Identifier: MIT
"""run() without Python models releases the GIL: another thread runs
Python meanwhile, and may neither step, run, re-initialise or set that
filter nor read it (RuntimeError, the run's results untouched), while
filters of their own sharing the same models step in parallel to the same
bits as alone."""
import copy
import threading

import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

N = 400_000


def kf2_setup(mod):
    car = mod.KF2Model(A=[[1, 0.1], [0, 1]], R=[[0.01, 0.02], [0.02, 0.04]])
    gps = mod.KF2Meas(C=[[1, 0]], Q=[[4]])
    z = np.sin(np.arange(N) * 1e-3)[:, None] * 10
    return car, gps, z


def ekf3_setup(mod):
    motion = mod.EKF3Motion(mod.forward_turn, np.eye(3) * 1e-3)
    meas = mod.EKF3Meas(mod.meas_xy, np.eye(2) * 0.1)
    k = np.arange(N)
    u = np.stack([np.full(N, 0.1), np.full(N, 0.01)], axis=1)
    z = np.stack([np.cos(k * 1e-2), np.sin(k * 1e-2)], axis=1) * 10
    return motion, meas, u, z


def start(fn):
    out = {}

    def target():
        try:
            out["result"] = fn()
        except BaseException as e:  # handed to the test's thread
            out["error"] = e
    th = threading.Thread(target=target)
    th.start()
    return th, out


def repr_probe(kf):
    """repr(kf), which never raises: while a run is on it shows no mean
    (RuntimeError here, as the other probes are refused); else the mean."""
    r = repr(kf)
    if r.endswith(" (a run in progress)>"):
        raise RuntimeError("a run() of this filter is in progress in another "
                           "thread: " + r)
    assert r.startswith("<gaussfilt.float") and " n=2 mu=[" in r, r


def busy(kf):
    """True while a run() of kf is in progress in another thread."""
    return repr(kf).endswith(" (a run in progress)>")


@pytest.mark.parametrize("mod", [float32, float64], ids=["f32", "f64"])
def test_another_thread_runs_and_may_not_touch_the_filter(mod):
    car, gps, z = kf2_setup(mod)
    alone = mod.KF2(mu=[0, 0], sigma=np.eye(2)).run(car, gps, z=z)
    # each probe fails either way, so the belief never changes: not finite
    # when the filter is idle, RuntimeError while the run is on
    nan = float("nan")
    pushed = mod.KF2Model(A=[[1, 0.1], [0, 1]], R=np.eye(2), B=np.eye(2))
    refused = {}
    # a run takes some 50 ms: on a busy machine this thread may not be
    # scheduled within one, so a few are tried
    for _ in range(20):
        kf = mod.KF2(mu=[0, 0], sigma=np.eye(2))
        probes = {
            "predict": lambda: kf.predict(pushed, u=[nan, nan]),
            "update": lambda: kf.update(gps, [nan]),
            "run": lambda: kf.run(pushed, u=[[nan, nan]]),
            "init": lambda: kf.__init__([nan, 0], np.eye(2)),
            "reset": lambda: kf.reset([nan, 0], np.eye(2)),
            "set mu": lambda: setattr(kf, "mu", [nan, 0]),
            "set sigma": lambda: setattr(kf, "sigma", [[nan, 0], [0, 1]]),
            # reads: the belief changes under them
            "mu": lambda: kf.mu,
            "sigma": lambda: kf.sigma,
            "nis": lambda: kf.nis,
            "innovation": lambda: kf.innovation,
            "S": lambda: kf.S,
            "K": lambda: kf.K,
            "loglik": lambda: kf.loglik,
            "copy": lambda: copy.copy(kf),
            "repr": lambda: repr_probe(kf),
        }
        # the run is the first to take the filter: no probe starts before
        # it is seen in progress, so none competes with it for the filter
        th, out = start(lambda: kf.run(car, gps, z=z))
        while th.is_alive() and not busy(kf):
            pass
        while th.is_alive() and len(refused) < len(probes):
            for name, call in probes.items():
                try:
                    call()
                except RuntimeError as e:
                    refused[name] = str(e)
                except gaussfilt.NonFinite:
                    pass
        th.join()
        assert "error" not in out, out.get("error")
        for a, b in zip(out["result"], alone):
            assert a.tobytes() == b.tobytes()
        np.testing.assert_array_equal(kf.mu, alone[0][-1])
        if len(refused) == len(probes):
            break
    # this thread ran while a run did, and every entry was refused
    assert sorted(refused) == sorted(probes), refused
    assert all("in progress in another thread" in msg
               for msg in refused.values()), refused
    assert "KF2.predict" in refused["predict"], refused


@pytest.mark.parametrize("mod", [float32, float64], ids=["f32", "f64"])
def test_filters_sharing_models_run_in_parallel_to_the_same_bits(mod):
    car, gps, z = kf2_setup(mod)
    motion, meas, u, z3 = ekf3_setup(mod)
    jobs = [lambda: mod.KF2(mu=[0, 0], sigma=np.eye(2)).run(car, gps, z=z),
            lambda: mod.EKF3(mu=[10, 0, 1.6], sigma=np.eye(3)).run(
                motion, meas, u=u, z=z3)]
    alone = [job() for job in jobs]
    threads = [start(job) for job in jobs + jobs]
    for th, _ in threads:
        th.join()
    for i, (_, out) in enumerate(threads):
        assert "error" not in out, out.get("error")
        for a, b in zip(out["result"], alone[i % 2]):
            assert a.tobytes() == b.tobytes()
