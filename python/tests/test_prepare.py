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

    def predicted(belief):
        """Predicts a fresh belief with the model: Sigma's bytes."""
        def run(model):
            f = belief(np.zeros(n), np.eye(n))
            f.predict(model)
            return f.sigma.tobytes()
        return run

    def updated(belief):
        """Updates a fresh belief with the measurement: mu's and Sigma's
        bytes."""
        def run(meas):
            f = belief(np.zeros(n), np.eye(n))
            f.update(meas, [1, 2])
            return f.mu.tobytes() + f.sigma.tobytes()
        return run

    return [
        ("KFModel", lambda: mod.KFModel(A, R), predicted(mod.KF)),
        ("KFMeas", lambda: mod.KFMeas(C, Q), updated(mod.KF)),
        ("EKFMotion", lambda: mod.EKFMotion(lambda mu, u: (mu, A), R),
         predicted(mod.EKF)),
        ("EKFMeas", lambda: mod.EKFMeas(lambda mu: (mu[:2], C), Q, n=n),
         updated(mod.EKF)),
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
