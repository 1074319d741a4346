# SPDX-License-Identifier: MIT
"""run() without Python models releases the GIL (KF2's and PF3's here):
another thread runs Python meanwhile, and may neither step, run,
re-initialise or set that filter nor read it (RuntimeError, the run's
results untouched), while filters of their own sharing the same models
step in parallel to the same bits as alone; a PF3 run with a Python h
keeps the GIL (its callback runs)."""
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


def ekf3_setup(mod, steps=N):
    motion = mod.EKF3Motion(mod.forward_turn, np.eye(3) * 1e-3)
    meas = mod.EKF3Meas(mod.meas_xy, np.eye(2) * 0.1)
    k = np.arange(steps)
    u = np.stack([np.full(steps, 0.1), np.full(steps, 0.01)], axis=1)
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


def probe_during(f, run, probes, refused):
    """Starts run (a run() of f) in another thread and, once it is seen in
    progress (so that no probe takes the filter before it), calls each
    probe until it is refused (RuntimeError, its message into refused) or
    the run ends; returns the run's outcome, which must not be an error."""
    th, out = start(run)
    while th.is_alive() and not busy(f):
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
    return out


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
        out = probe_during(kf, lambda: kf.run(car, gps, z=z), probes,
                           refused)
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


def pf3_state(pf):
    return pf.__getstate__()


@pytest.mark.parametrize("mod", [float32, float64], ids=["f32", "f64"])
def test_another_thread_may_not_touch_a_running_pf3(mod):
    motion, meas, u, z = ekf3_setup(mod, 2000)

    def fresh():
        return mod.PF3([10, 0, 1.6], np.eye(3), 100, seed=7)
    alone_pf = fresh()
    alone = alone_pf.run(motion, meas, u=u, z=z)
    nan = float("nan")
    refused = {}
    for _ in range(20):
        pf = fresh()

        def resample():
            # only while the run is seen on: an idle resample would draw
            if busy(pf):
                pf.resample()
        probes = {
            "predict": lambda: pf.predict(motion, [nan, nan]),
            "update": lambda: pf.update(meas, [nan, nan]),
            "run": lambda: pf.run(motion, u=[[nan, nan]]),
            "resample": resample,
            "init": lambda: pf.__init__([nan, 0, 0], np.eye(3), 10),
            "reset": lambda: pf.reset([nan, 0, 0], np.eye(3), 10),
            "mu": lambda: pf.mu,
            "sigma": lambda: pf.sigma,
            "particles": lambda: pf.particles,
            "weights": lambda: pf.weights,
            "neff": lambda: pf.neff,
            "loglik": lambda: pf.loglik,
            "copy": lambda: copy.copy(pf),
            "repr": lambda: pf3_repr_probe(pf),
        }
        out = probe_during(pf, lambda: pf.run(motion, meas, u=u, z=z),
                           probes, refused)
        for a, b in zip(out["result"], alone):
            assert a.tobytes() == b.tobytes()
        # every particle and the generator as the run alone left them
        assert pf3_state(pf) == pf3_state(alone_pf)
        if len(refused) == len(probes):
            break
    assert sorted(refused) == sorted(probes), refused
    assert all("in progress in another thread" in msg
               for msg in refused.values()), refused
    assert "PF3.predict" in refused["predict"], refused
    assert "PF3.resample" in refused["resample"], refused


def pf3_repr_probe(pf):
    r = repr(pf)
    if r.endswith(" (a run in progress)>"):
        raise RuntimeError("a run() of this filter is in progress in another "
                           "thread: " + r)
    assert r.startswith("<gaussfilt.float") and "PF3" in r, r


@pytest.mark.parametrize("mod", [float32, float64], ids=["f32", "f64"])
def test_pf3_runs_in_parallel_and_a_python_h_keeps_the_gil(mod):
    motion, meas, u, z = ekf3_setup(mod, 500)
    job = [lambda: mod.PF3([10, 0, 1.6], np.eye(3), 50, seed=3).run(
        motion, meas, u=u, z=z)]
    alone = job[0]()
    threads = [start(job[0]) for _ in range(3)]
    for th, out in threads:
        th.join()
        assert "error" not in out, out.get("error")
        for a, b in zip(out["result"], alone):
            assert a.tobytes() == b.tobytes()
    # with a Python h the run holds the GIL: the callback itself reads the
    # filter (allowed to its own callback), never refused as "in progress
    # in another thread"
    pf = mod.PF3([10, 0, 1.6], np.eye(3), 20, seed=3)
    seen = []

    def h(x):
        seen.append(repr(pf))
        return x[:2], np.zeros((2, 3))
    pf.run(motion, mod.EKF3Meas(h, np.eye(2) * 0.1), u=u[:3], z=z[:3])
    assert seen and not any("in progress" in r for r in seen), seen[:2]
