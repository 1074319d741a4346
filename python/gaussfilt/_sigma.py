# SPDX-License-Identifier: MIT
"""The array a filter's ``sigma`` property returns.

``sigma`` was a method (``f.sigma()``) and is a property now, as ``mu``
is. For one release the array it returns can still be called as the
method was: the call warns (DeprecationWarning) and returns the same
values as a plain ndarray. Everything else is a plain ndarray's: numpy
computes plain arrays from it, it prints and pickles as one. The call goes
in the next release.
"""
import warnings
from typing import Any

import numpy as np


class SigmaArray(np.ndarray):  # type: ignore[type-arg]
    """Sigma as read from ``f.sigma``: an ndarray, callable once more as
    the old ``f.sigma()`` (deprecated)."""

    def __call__(self) -> "np.ndarray[Any, Any]":
        warnings.warn(
            "f.sigma() is deprecated: sigma is a property, as mu is; write "
            "f.sigma (the call goes in the next release)",
            DeprecationWarning, stacklevel=2)
        return self.view(np.ndarray)

    def __array_wrap__(self, arr: Any, context: Any = None,
                       return_scalar: bool = False) -> Any:
        # what numpy computes from Sigma is a plain array (or scalar)
        arr = np.asarray(arr).view(np.ndarray)
        return arr[()] if return_scalar else arr

    def __reduce__(self) -> Any:
        return self.view(np.ndarray).__reduce__()

    def __repr__(self) -> str:
        return repr(self.view(np.ndarray))
