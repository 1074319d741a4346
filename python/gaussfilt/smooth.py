# SPDX-License-Identifier: MIT
"""rts_smooth: the Rauch-Tung-Striebel smoother over a recorded run.

    mu, sigma, nis, status = kf.run(model, meas, u=u, z=z)
    mu_s, sigma_s = gaussfilt.rts_smooth(mu, sigma, model, u=u)

From the last step back, with the filter's beliefs (mu_k, Sigma_k) after
each step's update and the model's A, B, c and R:

    mu_bar = A mu_k + B u_(k+1) + c,   Sigma_bar = A Sigma_k A^T + R,
    J_k = Sigma_k A^T Sigma_bar^-1,
    mu_s,k = mu_k + J_k (mu_s,k+1 - mu_bar),
    Sigma_s,k = Sigma_k + J_k (Sigma_s,k+1 - Sigma_bar) J_k^T.

It runs in numpy, in float64, over the C filter's outputs: smoothing is an
offline tool (a notebook's, a log's), not a step firmware takes, so it is
outside the bit-for-bit promise and gains nothing from the C core; float64
whatever the filter's precision. Sigma_bar is inverted through its
pseudo-inverse where it is singular (a state known exactly).
"""
from typing import Any, Optional, Tuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._errors import BadArgument

__all__ = ["rts_smooth"]


def rts_smooth(mu: ArrayLike, sigma: ArrayLike, model: Any,
               u: Optional[ArrayLike] = None
               ) -> Tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The smoothed means (N, n) and covariances (N, n, n) of a run's
    beliefs mu (N, n) and sigma (N, n, n), each after its step's update,
    for a linear model (KF2Model or KFModel: A, B, c, R); u (N, nu): the
    run's controls, u[k] applied in step k (None: none)."""
    m = np.asarray(mu, dtype=np.float64)
    s = np.asarray(sigma, dtype=np.float64)
    if m.ndim != 2 or s.ndim != 3 or s.shape != (m.shape[0], m.shape[1],
                                                  m.shape[1]):
        raise BadArgument("rts_smooth: mu must be (N, n) and sigma (N, n, n),"
                          " got %s and %s" % (m.shape, s.shape))
    if not all(hasattr(model, a) for a in ("A", "R")):
        raise BadArgument("rts_smooth: model must be a KF2Model or KFModel "
                          "(its A and R), not %s" % type(model).__name__)
    N, n = m.shape
    A = np.asarray(model.A, dtype=np.float64)
    R = np.asarray(model.R, dtype=np.float64)
    if A.shape != (n, n):
        raise BadArgument("rts_smooth: the model has %d states, the run %d"
                          % (A.shape[0], n))
    c = np.zeros(n) if model.c is None else np.asarray(model.c, np.float64)
    B = None if getattr(model, "B", None) is None else np.asarray(model.B,
                                                                   np.float64)
    U = None
    if u is not None:
        if B is None:
            raise BadArgument("rts_smooth: u given, the model has no B")
        U = np.asarray(u, dtype=np.float64).reshape(N, -1)
        if U.shape[1] != B.shape[1]:
            raise BadArgument("rts_smooth: u must be (N, %d), got %s"
                              % (B.shape[1], U.shape))
    if not (np.all(np.isfinite(m)) and np.all(np.isfinite(s))):
        raise BadArgument("rts_smooth: mu and sigma must be finite (a run's "
                          "rows after a failed step are not beliefs)")
    ms, ss = m.copy(), s.copy()
    for k in range(N - 2, -1, -1):
        mu_bar = A @ m[k] + c
        if U is not None and B is not None:
            mu_bar = mu_bar + B @ U[k + 1]
        P_bar = A @ s[k] @ A.T + R
        J = s[k] @ A.T @ np.linalg.pinv(P_bar, hermitian=True)
        ms[k] = m[k] + J @ (ms[k + 1] - mu_bar)
        S = s[k] + J @ (ss[k + 1] - P_bar) @ J.T
        ss[k] = (S + S.T) / 2
    return ms, ss
