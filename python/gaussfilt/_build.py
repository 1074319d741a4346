# SPDX-License-Identifier: MIT
"""What gaussfilt.float32 and gaussfilt.float64 hold: the names of one
build of the C library (the extension module _f32 or _f64), the
exceptions, and that build's numpy type ``dtype``.
"""
import numpy as np

from . import _errors

#: the extension module's names, in each precision module's __all__ order
_EXT_NAMES = ("KF2", "KF2Model", "KF2Meas", "EKF3", "EKF3Motion", "EKF3Meas",
              "KF", "KFModel", "KFMeas", "EKF", "EKFMotion", "EKFMeas",
              "UKF3", "PF3", "forward_turn", "meas_x", "meas_xy", "ellipse",
              "correlation", "marginal")
_CONSTANTS = ("NMAX", "PD_RTOL", "REAL_SIZE", "UKF3_ALPHA_MIN")
_ERRORS = ("GaussfiltError", "BadArgument", "NonFinite", "NotPSD",
           "Singular", "Gated", "Undefined", "ModelError")


def fill(namespace: dict, ext, real: str) -> None:
    """Puts ext's classes, functions and constants, the exceptions, dtype
    (numpy.dtype(real), the numpy type of ext's gf_real) and __all__ into
    namespace, a precision module's globals()."""
    for name in _EXT_NAMES + _CONSTANTS:
        namespace[name] = getattr(ext, name)
    for name in _ERRORS:
        namespace[name] = getattr(_errors, name)
    namespace["dtype"] = np.dtype(real)
    namespace["__all__"] = list(_EXT_NAMES + ("dtype",) + _CONSTANTS
                                + _ERRORS)
    # pickle and copy for the models (the beliefs have their own)
    from types import SimpleNamespace
    from ._state import register
    register(SimpleNamespace(**{n: namespace[n] for n in _EXT_NAMES}), real)
