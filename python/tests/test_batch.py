# SPDX-License-Identifier: MIT
"""The batch entries KF2.run, KF.run, EKF3.run and EKF.run: the same bits
as one call per step, gated steps recorded and skipped, NaN rows skipped,
and a failure (a callback's exception included) that puts the belief back
as it was."""
import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [pytest.param(float64, id="float64"), pytest.param(float32, id="float32")]


def run_and_steps(mod, make, model, meas, u, z):
    """Runs a fresh filter over u and z, steps another one call per step,
    and checks that each step's status, mu, Sigma and NIS are the same
    bits. Returns (the run's filter, the stepped one, status, nis)."""
    a = make()
    mu, sigma, nis, status = a.run(model, meas, u=u, z=z)
    b = make()
    for k in range(len(u)):
        b.predict(model, u[k])
        want_nis, st = np.nan, 0
        if not np.isnan(z[k, 0]):
            try:
                b.update(meas, z[k])
                want_nis = b.nis
            except gaussfilt.Gated as e:
                st, want_nis = e.status, e.nis
        assert status[k] == st, k
        assert mu[k].tobytes() == b.mu.tobytes(), k
        assert sigma[k].tobytes() == b.sigma.tobytes(), k
        assert np.array_equal(nis[k], mod.dtype.type(want_nis), equal_nan=True)
    return a, b, status, nis


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("n", [2, 4])
def test_run_equals_the_steps(mod, n):
    rng = np.random.default_rng(n)
    N = 200
    if n == 2:
        make = lambda: mod.KF2([0, 0], np.eye(2))
        model = mod.KF2Model([[1, 1], [0, 1]], [[0.25, 0.5], [0.5, 1]],
                             B=np.eye(2))
        meas = mod.KF2Meas([[1, 0]], [[10]], gate=9)
    else:
        make = lambda: mod.KF(np.zeros(n), np.eye(n))
        model = mod.KFModel(np.eye(n) + 0.1 * np.eye(n, k=1), np.eye(n) * 0.1,
                            B=np.ones((n, 1)))
        meas = mod.KFMeas(np.eye(1, n), [[1]], gate=9)
    u = rng.normal(size=(N, 2 if n == 2 else 1))
    z = rng.normal(size=(N, 1)) * 2
    z[::7] = np.nan   # no measurement
    z[5::11] += 40    # gated
    a, b, status, nis = run_and_steps(mod, make, model, meas, u, z)
    assert (status == -5).sum() > 5 and np.isnan(nis).sum() > 20
    assert a.mu.tobytes() == b.mu.tobytes() and a.nis == b.nis


@pytest.mark.parametrize("mod", MODS)
def test_a_failed_run_changes_nothing(mod):
    kf = mod.KF2([1, 2], np.eye(2))
    model = mod.KF2Model(np.eye(2), np.eye(2) * 0.1, B=np.eye(2))
    meas = mod.KF2Meas([[1, 0]], [[1]])
    kf.update(meas, [1.5])
    before = kf.mu.tobytes() + kf.sigma.tobytes(), kf.nis
    u = np.zeros((10, 2))
    u[6, 1] = np.inf
    with pytest.raises(gaussfilt.NonFinite) as e:
        kf.run(model, meas, u=u, z=np.ones((10, 1)))
    assert e.value.step == 6
    assert (kf.mu.tobytes() + kf.sigma.tobytes(), kf.nis) == before
    with pytest.raises(gaussfilt.BadArgument):
        kf.run(model, meas, u=np.zeros((10, 2)), z=np.ones((9, 1)))


def ekf_setup(mod, family, python_models):
    """A filter maker, a motion and a gated measurement, and (N, k) u and
    (N, m) z with NaN rows (no reading) and outliers (gated)."""
    dt = mod.dtype
    rng = np.random.default_rng(11)
    N = 120
    if family == "EKF3":
        make = lambda: mod.EKF3([0.5, -0.3, 2.9], np.diag([0.2, 0.3, 0.5]))
        if python_models:
            def g(mu, u):
                assert u.dtype == dt and u.shape == (2,)
                mb, G = mod.forward_turn(mu, u)
                return mb, G

            def h(mu):
                return mu[:2].copy(), [[1, 0, 0], [0, 1, 0]]
        else:
            g, h = mod.forward_turn, mod.meas_xy
        motion = mod.EKF3Motion(g, np.diag([0.01, 0.02, 0.005]))
        meas = mod.EKF3Meas(h, [[0.04, 0.01], [0.01, 0.05]], gate=9)
        u = np.column_stack([rng.uniform(0, 1, N), rng.uniform(-0.5, 0.5, N)])
        z = rng.normal(size=(N, 2))
    else:
        n = 4
        make = lambda: mod.EKF(np.zeros(n), np.eye(n))
        K3, DT = dt.type(0.01), dt.type(0.1)

        def g(mu, u):
            assert u.dtype == dt and u.shape == (1,)
            mb = mu + DT * np.roll(mu, -1) - K3 * mu * mu * mu + u[0]
            G = np.diag(1 - 3 * K3 * mu * mu) + DT * np.eye(n, k=1)
            G[n - 1, 0] = DT
            return mb, G

        def h(mu):
            return mu[:2] * mu[:2], np.diag(2 * mu)[:2]
        motion = mod.EKFMotion(g, np.eye(n) * 0.01)
        meas = mod.EKFMeas(h, np.eye(2) * 0.1, n=n, gate=9)
        u = rng.normal(size=(N, 1)) * 0.1
        z = np.abs(rng.normal(size=(N, 2)))
    z[::6] = np.nan
    z[4::13] += 40
    return make, motion, meas, u, z


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("family,python_models", [
    ("EKF3", False), ("EKF3", True), ("EKF", True)])
def test_ekf_run_equals_the_steps(mod, family, python_models):
    make, motion, meas, u, z = ekf_setup(mod, family, python_models)
    a, b, status, nis = run_and_steps(mod, make, motion, meas, u, z)
    assert (status == -5).sum() > 3 and np.isnan(nis).sum() > 15
    assert a.mu.tobytes() == b.mu.tobytes() and a.nis == b.nis
    assert a.innovation.tobytes() == b.innovation.tobytes()
    # predictions only, and updates only
    c, d = make(), make()
    mu_c = c.run(motion, u=u[:5])[0]
    for k in range(5):
        d.predict(motion, u[k])
        assert mu_c[k].tobytes() == d.mu.tobytes()
    zs = np.nan_to_num(z[:8], nan=0.5)
    nis_c, status_c = c.run(meas=meas, z=zs)[2:]
    for k in range(8):
        try:
            d.update(meas, zs[k])
            assert status_c[k] == 0 and np.float64(nis_c[k]) == d.nis
        except gaussfilt.Gated as e:
            assert status_c[k] == -5 and np.float64(nis_c[k]) == e.nis
    assert c.sigma.tobytes() == d.sigma.tobytes()


def snapshot(f):
    y = f.innovation
    return (f.mu.tobytes() + f.sigma.tobytes() + np.float64(f.nis).tobytes()
            + (b"none" if y is None else y.tobytes()))


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("family", ["EKF3", "EKF"])
@pytest.mark.parametrize("where", ["g", "h"])
def test_an_ekf_run_whose_callback_raises_changes_nothing(mod, family, where):
    make, motion, meas, u, z = ekf_setup(mod, family, True)
    filt = make()
    filt.update(meas, [0.5, 0.5])
    before = snapshot(filt)
    calls = [0]
    err = KeyError("step 9")
    fn = motion.g if where == "g" else meas.h

    def failing(*args):
        calls[0] += 1
        if calls[0] == 10:
            raise err
        return fn(*args)
    g = failing if where == "g" else motion.g
    h = failing if where == "h" else meas.h
    if family == "EKF3":
        bad_motion = mod.EKF3Motion(g, motion.R)
        bad_meas = mod.EKF3Meas(h, meas.Q, gate=9)
    else:
        bad_motion = mod.EKFMotion(g, motion.R)
        bad_meas = mod.EKFMeas(h, meas.Q, n=4, gate=9)
    zz = np.ones((20, 2))
    with pytest.raises(KeyError) as e:
        filt.run(bad_motion, bad_meas, u=u[:20], z=zz)
    assert e.value is err and e.value.step == 9
    assert snapshot(filt) == before
    # a library status in a run: NaN in z at step 3 is no reading, inf is
    # NonFinite
    zz[3, 0] = np.inf
    with pytest.raises(gaussfilt.NonFinite) as e:
        filt.run(motion, meas, u=u[:20], z=zz)
    assert e.value.step == 3
    assert snapshot(filt) == before


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("family", ["EKF3", "EKF"])
@pytest.mark.parametrize("inner", ["run", "update"])
def test_an_ekf_run_guards_its_filter(mod, family, inner):
    """A callback of a run calling run or update on the same filter gets
    RuntimeError; the run raises it (at step 0) and changes nothing."""
    make, motion, meas, u, z = ekf_setup(mod, family, True)
    filt = make()
    before = snapshot(filt)

    def g(mu, uk):
        if inner == "run":
            filt.run(motion, u=u[:1])
        else:
            filt.update(meas, [0.5, 0.5])
        return motion.g(mu, uk)
    bad = (mod.EKF3Motion if family == "EKF3" else mod.EKFMotion)(g, motion.R)
    with pytest.raises(RuntimeError, match="own callback") as e:
        filt.run(bad, u=u[:3])
    assert e.value.step == 0
    assert snapshot(filt) == before


@pytest.mark.parametrize("mod", MODS)
def test_ekf_run_arguments(mod):
    make, motion, meas, u, z = ekf_setup(mod, "EKF3", False)
    ekf3 = make()
    with pytest.raises(gaussfilt.BadArgument, match=r"u must have shape "
                       r"\(steps, 2\) for a built-in motion"):
        ekf3.run(motion, steps=3)
    with pytest.raises(gaussfilt.BadArgument, match=r"\(steps, 2\)"):
        ekf3.run(motion, u=np.zeros((3, 1)))
    with pytest.raises(gaussfilt.BadArgument, match=r"z must have shape "
                       r"\(steps, 2\)"):
        ekf3.run(motion, meas, u=u[:3], z=np.zeros((4, 2)))
    with pytest.raises(gaussfilt.BadArgument, match="z without meas"):
        ekf3.run(motion, u=u[:3], z=z[:3])
    with pytest.raises(gaussfilt.BadArgument, match="u without motion"):
        ekf3.run(meas=meas, u=u[:3], z=z[:3])
    with pytest.raises(gaussfilt.BadArgument, match="give u, z or steps"):
        ekf3.run()
    seen = []

    def g(mu, uk):
        seen.append(uk)
        return mu, np.eye(3)
    ekf3.run(mod.EKF3Motion(g, np.eye(3) * 0.01), steps=2)
    assert seen == [None, None]
    ekf = mod.EKF(np.zeros(2), np.eye(2))
    with pytest.raises(gaussfilt.BadArgument, match="the motion is for 3"):
        ekf.run(mod.EKFMotion(g, np.eye(3)), steps=1)
    out = ekf.run(steps=0)
    assert [a.shape for a in out] == [(0, 2), (0, 2, 2), (0,), (0,)]
