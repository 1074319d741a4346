# SPDX-License-Identifier: MIT
"""check_jacobians: correct models read small in both precisions (Python
callbacks and the built-in C models), a wrong entry is found where it is,
angle outputs are differenced across the wrap, and bad arguments raise."""
import math

import numpy as np
import pytest

import gaussfilt
from gaussfilt import check_jacobians
from gaussfilt import float32 as gf32
from gaussfilt import float64 as gf64

LANDMARK = np.array([4.0, 3.0])


def range_bearing(wrong=False, landmark=LANDMARK):
    def h(mu):
        dx, dy = landmark[0] - mu[0], landmark[1] - mu[1]
        q = dx * dx + dy * dy
        r = math.sqrt(q)
        bearing = math.atan2(dy, dx) - mu[2]
        H = np.array([[-dx / r, -dy / r, 0],
                      [(-dy if wrong else dy) / q, -dx / q, -1]])
        return np.array([r, bearing]), H
    return h


def test_a_correct_model_reads_small():
    meas = gf64.EKFMeas(h=range_bearing(), Q=np.eye(2), n=3, angle_mask=2)
    c = check_jacobians(meas, mu=[1, -0.5, 0.3])
    assert c.jacobian == "H" and c.worst < 1e-8
    assert c.errors.shape == (2, 3)


def test_a_wrong_entry_is_found():
    meas = gf64.EKFMeas(h=range_bearing(wrong=True), Q=np.eye(2), n=3,
                        angle_mask=2)
    c = check_jacobians(meas, mu=[1, -0.5, 0.3])
    assert (c.row, c.col) == (1, 0)
    assert abs(c.worst - 2) < 1e-6  # a sign
    assert abs(c.given + c.numeric) < 1e-6 * abs(c.numeric)
    assert "H[1][0]" in str(c)


def test_angles_are_differenced_across_the_wrap():
    h = range_bearing(landmark=np.array([-5.0, 0.0]))
    assert check_jacobians(h=h, mu=[0, 0, 0], angle_mask=2).worst < 1e-8
    assert check_jacobians(h=h, mu=[0, 0, 0], angle_mask=0).worst > 0.5


@pytest.mark.parametrize("mod,below", [(gf64, 1e-8), (gf32, 1e-2)])
def test_the_built_in_models(mod, below):
    motion = mod.EKF3Motion(g=mod.forward_turn, R=np.eye(3))
    c = check_jacobians(motion, mu=[1, 2, 3.1], u=[0.5, 0.2], angles=4)
    assert c.jacobian == "G" and c.worst < below
    meas = mod.EKF3Meas(h=mod.meas_xy, Q=np.eye(2))
    assert check_jacobians(meas, mu=[1, 2, 0.3]).worst < below


def test_bad_arguments():
    h = range_bearing()
    with pytest.raises(gaussfilt.BadArgument, match="one model"):
        check_jacobians(mu=[0, 0, 0])
    with pytest.raises(gaussfilt.BadArgument, match="one model"):
        check_jacobians(g=h, h=h, mu=[0, 0, 0])
    with pytest.raises(gaussfilt.BadArgument, match="motion or measurement"):
        check_jacobians(gf64.KF2Meas(C=[[1, 0]], Q=[[1]]), mu=[0, 0])
    with pytest.raises(gaussfilt.NonFinite):
        check_jacobians(h=h, mu=[math.nan, 0, 0])
    with pytest.raises(gaussfilt.BadArgument, match="entries"):
        check_jacobians(h=lambda mu: (mu[:1], np.eye(2)), mu=[0, 0, 0])
