# SPDX-License-Identifier: MIT
"""gaussfilt's C library built with gf_real = float64 (the module _f64).

Arrays given to it are rounded to numpy.float64; arrays it returns are
numpy.float64. See the package's docstring and docs/python.md.
"""
from . import _f64
from ._build import fill as _fill

_fill(globals(), _f64, "float64")
