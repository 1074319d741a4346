# SPDX-License-Identifier: MIT
"""The exceptions: one GaussfiltError subclass per gf_status other than OK.

Each carries the status code (``status``) and its C name (``status_name``);
Gated also the rejected update's innovation and NIS.
"""
from typing import Any, Optional

from numpy.typing import NDArray


class GaussfiltError(Exception):
    """A gaussfilt call returned a status other than GF_OK.

    The filter's belief is unchanged: the C library writes it only on
    success.
    """

    status: int = 0
    status_name: str = "GF_OK"
    #: the step of a run() that failed (None when raised by anything else)
    step: Optional[int] = None


class BadArgument(GaussfiltError, ValueError):
    """GF_ERR_ARG: a wrong shape, size, type or value range."""

    status = -1
    status_name = "GF_ERR_ARG"


class NonFinite(GaussfiltError, ValueError):
    """GF_ERR_NONFINITE: an input, or a model's output, is NaN or inf."""

    status = -2
    status_name = "GF_ERR_NONFINITE"


class NotPSD(GaussfiltError, ValueError):
    """GF_ERR_NOT_PSD: a covariance or noise matrix is not symmetric PSD."""

    status = -3
    status_name = "GF_ERR_NOT_PSD"


class Singular(GaussfiltError, ArithmeticError):
    """GF_ERR_SINGULAR: the innovation covariance S is not positive definite."""

    status = -4
    status_name = "GF_ERR_SINGULAR"


class Gated(GaussfiltError):
    """GF_ERR_GATED: the update's NIS exceeded the measurement's gate.

    ``innovation`` is y = z - z_hat and ``nis`` is y^T S^-1 y of the
    rejected update; the belief is the prediction, unchanged.
    """

    status = -5
    status_name = "GF_ERR_GATED"
    innovation: Optional[NDArray[Any]] = None
    nis: float = float("nan")


class Undefined(GaussfiltError, ValueError):
    """GF_ERR_UNDEFINED: the quantity is undefined here (a zero variance)."""

    status = -6
    status_name = "GF_ERR_UNDEFINED"


class ModelError(GaussfiltError):
    """GF_ERR_MODEL: a C model callback (a built-in) failed."""

    status = -7
    status_name = "GF_ERR_MODEL"


_BY_STATUS = {c.status: c for c in (BadArgument, NonFinite, NotPSD, Singular,
                                    Gated, Undefined, ModelError)}


def _from_status(status: int, message: str, innovation=None,
                 nis: float = float("nan")) -> GaussfiltError:
    """The exception for a status (called by the C extension)."""
    cls = _BY_STATUS.get(status)
    if cls is None:
        exc = GaussfiltError("%s (status %d)" % (message, status))
        exc.status = status
        exc.status_name = "unknown"
        return exc
    exc = cls(message)
    if cls is Gated:
        exc.innovation = innovation
        exc.nis = nis
    return exc
