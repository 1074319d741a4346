# SPDX-License-Identifier: MIT
"""gaussfilt's C library built with gf_real = float32 (the module _f32).

Arrays given to it are rounded to numpy.float32; arrays it returns are
numpy.float32. See the package's docstring and docs/python.md.
"""
from ._errors import (BadArgument, GaussfiltError, Gated, ModelError,
                      NonFinite, NotPSD, Singular, Undefined)
from ._f32 import (EKF, EKF3, KF, KF2, NMAX, PD_RTOL, REAL_SIZE, EKF3Meas,
                   EKF3Motion, EKFMeas, EKFMotion, KF2Meas, KF2Model, KFMeas,
                   KFModel, correlation, ellipse, forward_turn, marginal,
                   meas_x, meas_xy)
import numpy as _np

#: the numpy type of this build's gf_real
dtype = _np.dtype(_np.float32)

__all__ = ["KF2", "KF2Model", "KF2Meas", "EKF3", "EKF3Motion", "EKF3Meas",
           "KF", "KFModel", "KFMeas", "EKF", "EKFMotion", "EKFMeas",
           "forward_turn", "meas_x", "meas_xy", "ellipse", "correlation",
           "marginal", "dtype", "NMAX", "PD_RTOL", "REAL_SIZE",
           "GaussfiltError", "BadArgument", "NonFinite", "NotPSD",
           "Singular", "Gated", "Undefined", "ModelError"]
