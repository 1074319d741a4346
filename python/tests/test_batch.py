# SPDX-License-Identifier: MIT
"""The batch entry KF2.run / KF.run: the same bits as one call per step,
gated steps recorded and skipped, NaN rows skipped, and a failure that
puts the belief back as it was."""
import numpy as np
import pytest

import gaussfilt
from gaussfilt import float32, float64

MODS = [pytest.param(float64, id="float64"), pytest.param(float32, id="float32")]


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
    a = make()
    mu, sigma, nis, status = a.run(model, meas, u=u, z=z)
    b = make()
    for k in range(N):
        b.predict(model, u[k])
        want_nis = np.nan
        st = 0
        if not np.isnan(z[k, 0]):
            try:
                b.update(meas, z[k])
                want_nis = b.nis
            except gaussfilt.Gated as e:
                st, want_nis = e.status, e.nis
        assert status[k] == st
        assert mu[k].tobytes() == b.mu.tobytes()
        assert sigma[k].tobytes() == b.sigma().tobytes()
        assert np.array_equal(nis[k], mod.dtype.type(want_nis), equal_nan=True)
    assert (status == -5).sum() > 5 and np.isnan(nis).sum() > 20
    assert a.mu.tobytes() == b.mu.tobytes() and a.nis == b.nis


@pytest.mark.parametrize("mod", MODS)
def test_a_failed_run_changes_nothing(mod):
    kf = mod.KF2([1, 2], np.eye(2))
    model = mod.KF2Model(np.eye(2), np.eye(2) * 0.1, B=np.eye(2))
    meas = mod.KF2Meas([[1, 0]], [[1]])
    kf.update(meas, [1.5])
    before = kf.mu.tobytes() + kf.sigma().tobytes(), kf.nis
    u = np.zeros((10, 2))
    u[6, 1] = np.inf
    with pytest.raises(gaussfilt.NonFinite) as e:
        kf.run(model, meas, u=u, z=np.ones((10, 1)))
    assert e.value.step == 6
    assert (kf.mu.tobytes() + kf.sigma().tobytes(), kf.nis) == before
    with pytest.raises(gaussfilt.BadArgument):
        kf.run(model, meas, u=np.zeros((10, 2)), z=np.ones((9, 1)))
