# SPDX-License-Identifier: MIT
"""gaussfilt's C library built with gf_real = float32 (the module _f32).

Arrays given to it are rounded to numpy.float32; arrays it returns are
numpy.float32. See the package's docstring and docs/python.md.
"""
from . import _f32
from ._build import fill as _fill

_fill(globals(), _f32, "float32")
