# SPDX-License-Identifier: MIT
"""Pickle and copy for the built-in EKF3 models (copyreg).

A belief (KF2, EKF3, KF, EKF, UKF3, PF3) pickles through its own __getstate__ and
__setstate__ (every bit of its factors), a model through its own
__reduce__ and __setstate__ (rebuilt from its arguments, which factors it
again to the same bits; an EKF model's g or h pickles as pickle can: a
module-level function does, a lambda does not); both carry a subclass's
instance attributes. A built-in model pickles by its name in its
precision's module, so that it loads as the same object.
"""
import copyreg
from typing import Any, Callable, Tuple


def _builtin(precision: str, name: str) -> Any:
    from . import float32, float64
    return getattr(float32 if precision == "float32" else float64, name)


def register(module: Any, precision: str) -> None:
    """The copyreg reduction of one precision module's built-in models."""
    m = module
    names = {id(getattr(m, n)): n for n in ("forward_turn", "meas_x",
                                            "meas_xy")}

    def builtin(b: Any) -> Tuple[Callable[..., Any], Tuple[Any, ...]]:
        return _builtin, (precision, names[id(b)])

    copyreg.pickle(type(m.forward_turn), builtin)
