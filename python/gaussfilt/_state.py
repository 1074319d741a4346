# SPDX-License-Identifier: MIT
"""Pickle and copy for the models and the built-in models (copyreg).

A belief (KF2, EKF3, KF, EKF) pickles through its own __getstate__ and
__setstate__ (every bit of its factors). A model is rebuilt from what it
was given (its getters), which factors it again to the same bits; an EKF
model's g or h pickles as pickle can (a module-level function does, a
lambda does not); a built-in model by its name in its precision's module.
"""
import copyreg
from typing import Any, Callable, Tuple


def _builtin(precision: str, name: str) -> Any:
    from . import float32, float64
    return getattr(float32 if precision == "float32" else float64, name)


def register(module: Any, precision: str) -> None:
    """copyreg reductions for one precision module's models."""
    m = module
    names = {id(getattr(m, n)): n for n in ("forward_turn", "meas_x",
                                            "meas_xy")}

    def builtin(b: Any) -> Tuple[Callable[..., Any], Tuple[Any, ...]]:
        return _builtin, (precision, names[id(b)])

    copyreg.pickle(type(m.forward_turn), builtin)
    copyreg.pickle(m.KF2Model, lambda o: (m.KF2Model, (o.A, o.R, o.B, o.c)))
    copyreg.pickle(m.KF2Meas, lambda o: (m.KF2Meas, (o.C, o.Q, o.c, o.gate)))
    copyreg.pickle(m.KFModel, lambda o: (m.KFModel, (o.A, o.R, o.B, o.c)))
    copyreg.pickle(m.KFMeas, lambda o: (m.KFMeas, (o.C, o.Q, o.c, o.gate)))
    copyreg.pickle(m.EKF3Motion, lambda o: (m.EKF3Motion, (o.g, o.R)))
    copyreg.pickle(m.EKF3Meas, lambda o: (
        m.EKF3Meas, (o.h, o.Q, o.angle_mask, o.gate)))
    copyreg.pickle(m.EKFMotion, lambda o: (m.EKFMotion, (o.g, o.R)))
    copyreg.pickle(m.EKFMeas, lambda o: (
        m.EKFMeas, (o.h, o.Q, o.n, o.angle_mask, o.gate)))
