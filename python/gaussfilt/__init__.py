# SPDX-License-Identifier: MIT
"""gaussfilt: the C library's Gaussian filters, called from Python.

Two builds of the same C sources, one per precision::

    from gaussfilt import float64 as gf     # gf_real = double
    from gaussfilt import float32 as gf32   # gf_real = float, as on an MCU

Each has KF2, EKF3, KF, EKF, UKF3 and PF3 (beliefs; UKF3 and PF3 take
EKF3's models), their models (KF2Model, KF2Meas, EKF3Motion, EKF3Meas, KFModel,
KFMeas, EKFMotion, EKFMeas), the built-in EKF3 models forward_turn, meas_x
and meas_xy, and the 2x2 helpers ellipse, correlation and marginal. The book's names: R is the process
noise, Q the measurement noise (FilterPy's Q and R). Every status other
than GF_OK raises a GaussfiltError subclass (BadArgument, NonFinite,
NotPSD, Singular, Gated, Undefined, ModelError); the belief is unchanged
then. Recorder and export_c write a run recorded in Python as a C program
that checks itself against the library, bit for bit; check_jacobians
compares a model's Jacobians with central differences. docs/python.md has
the whole API.
"""
from ._errors import (BadArgument, GaussfiltError, Gated, ModelError,
                      NonFinite, NotPSD, Singular, Undefined)
from . import float32, float64
from .check import JacobianCheck, check_jacobians
from .export import Recorder, export_c
from .smooth import rts_smooth

__all__ = ["float32", "float64", "GaussfiltError", "BadArgument",
           "NonFinite", "NotPSD", "Singular", "Gated", "Undefined",
           "ModelError", "Recorder", "export_c", "check_jacobians",
           "JacobianCheck", "rts_smooth"]
__version__ = "0.1.0"
