# SPDX-License-Identifier: MIT
"""check_jacobians: a model's Jacobians against central differences of its
function, as the C library's gf_ekf_check_model computes them.

    from gaussfilt import float64 as gf, check_jacobians
    c = check_jacobians(gf.EKFMeas(h=h, Q=Q, n=3), mu=[1, -0.5, 0.3])
    print(c)   # worst 2 at H[1][0]: given -0.1647, numeric 0.1647

For each state j, D_ij = (f_i(mu + h_j e_j) - f_i(mu - h_j e_j)) / (2 h_j)
with h_j = 2^-17 max(|mu_j|, 1) in float64 (2^-8 in float32: about
eps^(1/3)), the differences of angle outputs wrapped to (-pi, pi]; the
entry's difference is |J_ij - D_ij| / max(|J_ij|, |D_ij|, 1000 eps
(|f_i(mu + h_j e_j)| + |f_i(mu - h_j e_j)|) / 2h_j). A correct, smooth
model reads below about 1e-8 in float64 and 1e-2 in float32; a wrong
entry about 1 (a sign: 2).
"""
import math
from dataclasses import dataclass
from typing import Any, Callable, Optional

import numpy as np
from numpy.typing import ArrayLike, DTypeLike, NDArray

from ._errors import BadArgument, NonFinite

__all__ = ["JacobianCheck", "check_jacobians"]


@dataclass
class JacobianCheck:
    """The worst entry (and every entry's difference, in `errors`)."""
    worst: float
    jacobian: str  # "G" (a motion's) or "H" (a measurement's)
    row: int
    col: int
    given: float
    numeric: float
    errors: NDArray[np.float64]

    def __str__(self) -> str:
        return ("worst %.3g at %s[%d][%d]: given %.6g, numeric %.6g"
                % (self.worst, self.jacobian, self.row, self.col, self.given,
                   self.numeric))


def _wrap(a: Any) -> Any:
    return a - 2 * math.pi * np.floor((a + math.pi) / (2 * math.pi))


def check_jacobians(model: Any = None, mu: Optional[ArrayLike] = None,
                    u: Optional[ArrayLike] = None, *,
                    g: Optional[Callable[..., Any]] = None,
                    h: Optional[Callable[..., Any]] = None, angles: int = 0,
                    angle_mask: Optional[int] = None,
                    dtype: DTypeLike = None) -> JacobianCheck:
    """Compares a model's Jacobian with central differences at mu.

    model: an EKFMotion or EKF3Motion (its g is called as g(mu, u)), or an
    EKFMeas or EKF3Meas (h(mu), its angle_mask wrapping the residuals); or
    give a function as g= or h= instead. angles: the bits of g's outputs
    that are angles (the belief's `angles`); angle_mask: h's, when h is
    given alone. dtype: the precision the functions compute in (default:
    the model's module's, else float64). Returns a JacobianCheck."""
    if (model is None) == (g is None and h is None) or (g is not None and
                                                        h is not None):
        raise BadArgument("check_jacobians: give one model, or one of g= "
                          "and h=")
    if model is not None:
        if hasattr(model, "g"):
            g = model.g
        elif hasattr(model, "h"):
            h = model.h
            if angle_mask is None:
                angle_mask = model.angle_mask
        else:
            raise BadArgument("check_jacobians: model must be an EKF or "
                              "EKF3 motion or measurement, not %s"
                              % type(model).__name__)
        if dtype is None:
            dtype = np.float32 if type(model).__module__.endswith(
                "float32") else np.float64
    dtype = np.dtype(np.float64 if dtype is None else dtype)
    if dtype not in (np.float32, np.float64):
        raise BadArgument("check_jacobians: dtype must be float32 or float64")
    if mu is None:
        raise BadArgument("check_jacobians: mu is needed")
    x0 = np.array(mu, dtype=dtype).reshape(-1)
    if not np.all(np.isfinite(x0)):
        raise NonFinite("check_jacobians: mu is not finite")
    n = x0.size
    wrap = angles if g is not None else (angle_mask or 0)
    eps = float(np.finfo(dtype).eps)
    step = 2.0 ** -8 if dtype == np.float32 else 2.0 ** -17

    def call(x):
        f, J = g(x.copy(), u) if g is not None else h(x.copy())
        f = np.asarray(f, dtype=np.float64).reshape(-1)
        if np.size(J) != f.size * n:
            raise BadArgument("check_jacobians: the Jacobian has %d entries, "
                              "not %d x %d" % (np.size(J), f.size, n))
        J = np.asarray(J, dtype=np.float64).reshape(f.size, n)
        if not (np.all(np.isfinite(f)) and np.all(np.isfinite(J))):
            raise NonFinite("check_jacobians: the model's answer at %s is "
                            "not finite" % (x,))
        return f, J

    _, J0 = call(x0)
    rows = J0.shape[0]
    errors = np.zeros((rows, n))
    D = np.zeros((rows, n))
    for j in range(n):
        a = max(abs(float(x0[j])), 1.0)
        xp, xm = x0.copy(), x0.copy()
        xp[j] = x0[j] + dtype.type(step * a)
        xm[j] = x0[j] - dtype.type(step * a)
        fp, _ = call(xp)
        fm, _ = call(xm)
        d = fp - fm
        for i in range(rows):
            if i < 32 and (wrap >> i) & 1:
                d[i] = _wrap(d[i])
        hd = float(xp[j]) - float(xm[j])
        D[:, j] = d / hd
        floor = 1000 * eps * (np.abs(fp) + np.abs(fm)) / hd
        den = np.maximum(np.maximum(np.abs(J0[:, j]), np.abs(D[:, j])), floor)
        with np.errstate(invalid="ignore", divide="ignore"):
            errors[:, j] = np.where(den > 0,
                                    np.abs(J0[:, j] - D[:, j]) / den, 0.0)
    i, j = np.unravel_index(int(np.argmax(errors)), errors.shape)
    return JacobianCheck(float(errors[i, j]), "G" if g is not None else "H",
                         int(i), int(j), float(J0[i, j]), float(D[i, j]),
                         errors)
