# SPDX-License-Identifier: MIT
"""Models prepared while the heap is churned: each KFModel, KFMeas,
EKFMotion and EKFMeas gets the factors of its own noise matrix.

A model is checked and factored once, when built, in a workspace the
package allocates for the call, on a heap full of freed workspaces: what
an earlier workspace left there must never reach a model, so each model
must step as the first one built did.
"""
import numpy as np
import pytest

from gaussfilt import float32, float64

MODS = [pytest.param(float64, id="float64"), pytest.param(float32, id="float32")]
ROUNDS = 600


def kinds(mod, n):
    """(name, make a model, step a fresh filter with it -> bytes)."""
    R = np.eye(n) * 0.01 + 0.001
    Q = np.eye(2) * 0.5 + 0.1
    A = np.eye(n)
    C = np.eye(2, n)

    def run_kf_model(model):
        f = mod.KF(np.zeros(n), np.eye(n))
        f.predict(model)
        return f.sigma().tobytes()

    def run_kf_meas(meas):
        f = mod.KF(np.zeros(n), np.eye(n))
        f.update(meas, [1, 2])
        return f.mu.tobytes() + f.sigma().tobytes()

    def run_ekf_motion(motion):
        f = mod.EKF(np.zeros(n), np.eye(n))
        f.predict(motion)
        return f.sigma().tobytes()

    def run_ekf_meas(meas):
        f = mod.EKF(np.zeros(n), np.eye(n))
        f.update(meas, [1, 2])
        return f.mu.tobytes() + f.sigma().tobytes()

    return [
        ("KFModel", lambda: mod.KFModel(A, R), run_kf_model),
        ("KFMeas", lambda: mod.KFMeas(C, Q), run_kf_meas),
        ("EKFMotion", lambda: mod.EKFMotion(lambda mu, u: (mu, A), R),
         run_ekf_motion),
        ("EKFMeas", lambda: mod.EKFMeas(lambda mu: (mu[:2], C), Q, n=n),
         run_ekf_meas),
    ]


@pytest.mark.parametrize("mod", MODS)
@pytest.mark.parametrize("n", [2, 6, 12])
def test_models_built_on_a_churned_heap_get_their_own_factors(mod, n):
    rng = np.random.default_rng(n)
    for name, make, run in kinds(mod, n):
        want = run(make())
        junk, wrong = [], 0
        for _ in range(ROUNDS):
            wrong += run(make()) != want
            # buffers of the workspace's size and smaller, and filters
            # (each holds a workspace), kept and freed at random
            junk.append([np.empty(int(rng.integers(1, 3000)), np.uint8)
                         for _ in range(3)])
            junk.append(mod.EKF(np.zeros(n), np.eye(n)))
            if len(junk) > 40:
                del junk[:int(rng.integers(1, 40))]
        assert wrong == 0, "%s: %d of %d built wrong" % (name, wrong, ROUNDS)
