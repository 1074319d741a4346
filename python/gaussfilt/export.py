# SPDX-License-Identifier: MIT
"""Back to C: a run recorded in Python as a C program that checks itself.

    from gaussfilt import float32 as gf, Recorder, export_c

    rec = Recorder(gf.KF2, mu=[0, 0], sigma=[[1, 0], [0, 1]])
    rec.predict(car)            # the filter's own steps, recorded
    rec.update(gps, z=[5])
    export_c(rec, "car_run.c")  # the models, inputs and every result

The C file needs only the vendored library (include/ and src/): built in
the recorded precision (float32: GF_SINGLE_PRECISION), it runs the same
calls through the library's plain API and compares every status, mean,
covariance (through the accessor), innovation and NIS with the recorded
ones, as bytes. `NAME_check()` returns 0 when all are equal; a main()
printing the verdict is compiled unless GF_EXPORT_NO_MAIN is defined.

Recorded: KF2 and KF with their linear models, EKF3 with the built-in
models (forward_turn, meas_x, meas_xy). A Python g or h has no C to
write, so an EKF3 step with one, and the EKF, are refused when recorded.
A step that raises is recorded with its status (the belief unchanged, as
the library leaves it), except BadArgument, which the package raises for
the arguments' shapes and types before the library is called.
"""
import datetime
import os
import pathlib
import re
from typing import Any, Callable, Dict, List, Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._errors import BadArgument, GaussfiltError

__all__ = ["Recorder", "export_c"]

_KINDS = ("KF2", "KF", "EKF3")


def _module_of(cls):
    import importlib
    return importlib.import_module(cls.__module__)


class Recorder:
    """A filter of class `cls` (KF2, KF or EKF3 of gaussfilt.float32 or
    gaussfilt.float64) built from mu and sigma, whose predict and update
    calls are recorded for export_c. The filter is `rec.filter`; mu, sigma,
    nis and innovation read through to it."""

    def __init__(self, cls: Callable[..., Any], mu: ArrayLike,
                 sigma: ArrayLike) -> None:
        if getattr(cls, "__name__", None) not in _KINDS:
            raise BadArgument("Recorder: cls must be KF2, KF or EKF3 of "
                              "gaussfilt.float32 or gaussfilt.float64, not %r"
                              % (cls,))
        self.kind = cls.__name__
        self.module = _module_of(cls)
        self.filter = cls(mu=mu, sigma=sigma)
        self.dtype = np.dtype(self.module.dtype)
        self.mu0 = np.array(mu, dtype=self.dtype).reshape(-1)
        self.sigma0 = np.array(sigma, dtype=self.dtype)
        self.n = self.mu0.size
        self.steps: List[Dict[str, Any]] = []

    @property
    def mu(self) -> NDArray[Any]:
        mu: NDArray[Any] = self.filter.mu
        return mu

    @property
    def nis(self) -> float:
        return float(self.filter.nis)

    @property
    def innovation(self) -> Optional[NDArray[Any]]:
        y: Optional[NDArray[Any]] = self.filter.innovation
        return y

    def sigma(self) -> NDArray[Any]:
        return _sigma_of(self.filter)

    def predict(self, model: Any, u: Optional[ArrayLike] = None) -> None:
        """The filter's predict(model, u), recorded."""
        if self.kind == "EKF3" and model.g is not self.module.forward_turn:
            raise BadArgument("Recorder.predict: an EKF3 motion is recorded "
                              "only with the built-in forward_turn (a Python "
                              "g has no C to export)")
        uu = None if u is None else np.array(u, dtype=self.dtype).reshape(-1)
        self._step("predict", model, uu,
                   lambda: self.filter.predict(model, u))

    def update(self, meas: Any, z: ArrayLike) -> None:
        """The filter's update(meas, z), recorded."""
        if self.kind == "EKF3" and not (meas.h is self.module.meas_x or
                                        meas.h is self.module.meas_xy):
            raise BadArgument("Recorder.update: an EKF3 measurement is "
                              "recorded only with the built-in meas_x or "
                              "meas_xy (a Python h has no C to export)")
        zz = np.array(z, dtype=self.dtype).reshape(-1)
        self._step("update", meas, zz, lambda: self.filter.update(meas, z))

    def _step(self, op, model, arg, call):
        try:
            call()
        except BadArgument:
            raise  # the package's own refusal: the library was not called
        except GaussfiltError as e:
            # a gated update's innovation and NIS reach the C call's info
            gated = getattr(e, "innovation", None) is not None
            self._record(op, model, arg, e.status,
                         e.innovation if gated else None,
                         e.nis if gated else None)
            raise
        f = self.filter
        self._record(op, model, arg, 0,
                     f.innovation if op == "update" else None, f.nis)

    def _record(self, op, model, arg, status, y, nis):
        f = self.filter
        self.steps.append({
            "op": op, "model": model, "arg": arg, "status": status,
            "mu": np.array(f.mu, dtype=self.dtype),
            "sigma": np.array(_sigma_of(f), dtype=self.dtype),
            # what the update's info receives (on GF_OK and GF_ERR_GATED)
            "y": None if y is None else np.array(y, dtype=self.dtype),
            "nis": self.dtype.type(0.0 if nis is None else nis),
        })


def _sigma_of(f: Any) -> NDArray[Any]:
    s = f.sigma
    sigma: NDArray[Any] = s() if callable(s) else s
    return sigma


# ---- the C text ---------------------------------------------------------

def _lit(x, single):
    v = float(x)
    if v != v or v in (float("inf"), float("-inf")):
        raise BadArgument("export_c: a recorded value is not finite (%r)" % v)
    mant, exp = v.hex().split("p")
    if "." in mant:
        mant = mant.rstrip("0").rstrip(".")
    return mant + "p" + exp + ("f" if single else "")


def _arr(xs, single):
    return "{" + ", ".join(_lit(x, single) for x in np.ravel(xs)) + "}"


def _padded(xs, size, single):
    flat = list(np.ravel(xs)) + [0.0] * (size - np.size(xs))
    return _arr(flat, single)


def _mat(a, rows, cols, single):
    """A gf_mat2 / gf_mat3 initializer of a (rows x cols, padded with 0)."""
    a = np.zeros((0, 0)) if a is None else np.atleast_2d(a)
    out = []
    for i in range(rows):
        row = [float(a[i, j]) if i < a.shape[0] and j < a.shape[1] else 0.0
               for j in range(cols)]
        out.append(_arr(row, single))
    return "{{" + ", ".join(out) + "}}"


def _vec(v, size, single):
    return "{" + _padded(np.zeros(0) if v is None else v, size, single) + "}"


def export_c(recorder: Recorder, path: Union[str, "os.PathLike[str]"],
             name: Optional[str] = None) -> pathlib.Path:
    """Writes the run recorded by `recorder` (a Recorder) to `path` as a C
    program that checks itself against the library, bit for bit; `name`
    (a C identifier, default from the file name) prefixes its check
    function, NAME_check(). Returns the path (a pathlib.Path)."""
    if not isinstance(recorder, Recorder):
        raise BadArgument("export_c: recorder must be a gaussfilt Recorder, "
                          "not %s" % type(recorder).__name__)
    path = pathlib.Path(path)
    if name is None:
        name = re.sub(r"\W", "_", path.stem)
        name = name if re.match(r"[A-Za-z_]", name) else "run_" + name
    if not re.fullmatch(r"[A-Za-z_]\w*", name):
        raise BadArgument("export_c: name must be a C identifier, not %r"
                          % name)
    text = _program(recorder, name)
    with open(path, "w") as fh:
        fh.write(text)
    return path


def _program(rec, name):
    single = rec.dtype == np.float32
    n = rec.n
    kind = rec.kind
    models, index = [], {}
    for s in rec.steps:
        key = id(s["model"])
        if key not in index:
            index[key] = len(models)
            models.append(s["model"])
    L = []
    L.append("// Generated by gaussfilt.export_c on %s: a %s run of %d "
             "steps in %s,"
             % (datetime.date.today().isoformat(), kind, len(rec.steps),
                "float32" if single else "float64"))
    L.append("// recorded in Python. It runs the same calls through the "
             "library's plain API and")
    L.append("// compares every status, mean, covariance, innovation and "
             "NIS with the recorded")
    L.append("// ones as bytes: %s_check() returns 0 when all are equal "
             "(main() prints it" % name)
    L.append("// unless GF_EXPORT_NO_MAIN is defined). Needs gaussfilt's "
             "include/ and src/,")
    L.append("// built with -ffp-contract=off (the library's CMakeLists.txt "
             "does). Do not edit.")
    L.append("#include <string.h>")
    L.append("")
    L.append('#include "gaussfilt/gaussfilt.h"')
    L.append("")
    if single:
        L.append("#ifndef GF_SINGLE_PRECISION")
        L.append('#error "recorded with gaussfilt.float32: build with '
                 'GF_SINGLE_PRECISION (-DGAUSSFILT_SINGLE_PRECISION=ON)"')
    else:
        L.append("#ifdef GF_SINGLE_PRECISION")
        L.append('#error "recorded with gaussfilt.float64: build without '
                 'GF_SINGLE_PRECISION"')
    L.append("#endif")
    if kind == "KF":
        L.append("#if GF_KF_NMAX < %d" % n)
        L.append('#error "the run has %d states: GF_KF_NMAX must be at '
                 'least that"' % n)
        L.append("#endif")
    L.append("")
    width = max([n] + [len(s["arg"]) for s in rec.steps
                       if s["arg"] is not None])
    L.append("// One recorded call: predict (op 0) or update (op 1) with "
             "model `which`; in:")
    L.append("// u (has_in: given) or z; then what the library answered.")
    L.append("typedef struct {")
    L.append("    unsigned char op, which, has_in;")
    L.append("    int status;")
    L.append("    gf_real in[%d];" % width)
    L.append("    gf_real mu[%d];" % n)
    L.append("    gf_real sigma[%d];" % (n * n))
    L.append("    gf_real y[%d];" % n)
    L.append("    gf_real nis;")
    L.append("} %s_step;" % name)
    L.append("")
    L.append("static const gf_real %s_mu0[%d] = %s;"
             % (name, n, _arr(rec.mu0, single)))
    L.append("static const gf_real %s_sigma0[%d] = %s;"
             % (name, n * n, _arr(rec.sigma0, single)))
    L.append("")
    L.extend(_models(rec, name, models, single))
    L.append("static const %s_step %s_steps[%d] = {"
             % (name, name, max(1, len(rec.steps))))
    for s in rec.steps:
        arg = s["arg"]
        has = arg is not None
        upd = s["op"] == "update" and s["status"] in (0, -5) and \
            s["y"] is not None
        L.append("    {%d, %d, %d, %d, %s, %s, %s, %s, %s}," % (
            0 if s["op"] == "predict" else 1, index[id(s["model"])],
            1 if has else 0, s["status"],
            _padded(arg if has else [], width, single),
            _arr(s["mu"], single), _arr(s["sigma"], single),
            _padded(s["y"] if upd else [], n, single),
            _lit(s["nis"] if upd else 0.0, single)))
    if not rec.steps:
        L.append("    {0, 0, 0, 0, {0}, {0}, {0}, {0}, 0},")
    L.append("};")
    L.append("")
    L.extend(_check(rec, name, single))
    return "\n".join(L) + "\n"


def _models(rec, name, models, single):
    L = []
    n = rec.n
    if rec.kind == "KF2":
        for m in models:
            i = models.index(m)
            if hasattr(m, "A"):
                L.append("static const gf_kf2_model %s_model%d = {%s, %s, "
                         "%s, %s};" % (name, i, _mat(m.A, 2, 2, single),
                                       _mat(m.B, 2, 2, single),
                                       _mat(m.R, 2, 2, single),
                                       _vec(m.c, 2, single)))
            else:
                L.append("static const gf_kf2_meas %s_model%d = {%du, %s, "
                         "%s, %s, %s};" % (name, i, m.m,
                                           _mat(m.C, 2, 2, single),
                                           _mat(m.Q, 2, 2, single),
                                           _vec(m.c, 2, single),
                                           _lit(m.gate, single)))
    elif rec.kind == "KF":
        for i, m in enumerate(models):
            p = "%s_model%d" % (name, i)
            if hasattr(m, "A"):
                L.append("static const gf_real %s_A[%d] = %s;"
                         % (p, n * n, _arr(m.A, single)))
                L.append("static const gf_real %s_R[%d] = %s;"
                         % (p, n * n, _arr(m.R, single)))
                if m.B is not None:
                    L.append("static const gf_real %s_B[%d] = %s;"
                             % (p, np.size(m.B), _arr(m.B, single)))
                if m.c is not None:
                    L.append("static const gf_real %s_c[%d] = %s;"
                             % (p, n, _arr(m.c, single)))
                L.append("static const gf_kf_model %s = {%du, %s_A, %s, "
                         "%s_R, %s};" % (p, m.nu, p,
                                         p + "_B" if m.B is not None
                                         else "NULL", p,
                                         p + "_c" if m.c is not None
                                         else "NULL"))
            else:
                L.append("static const gf_real %s_C[%d] = %s;"
                         % (p, np.size(m.C), _arr(m.C, single)))
                L.append("static const gf_real %s_Q[%d] = %s;"
                         % (p, np.size(m.Q), _arr(m.Q, single)))
                if m.c is not None:
                    L.append("static const gf_real %s_c[%d] = %s;"
                             % (p, m.m, _arr(m.c, single)))
                L.append("static const gf_kf_meas %s = {%du, %s_C, %s_Q, "
                         "%s, %s};" % (p, m.m, p, p,
                                       p + "_c" if m.c is not None
                                       else "NULL", _lit(m.gate, single)))
    else:  # EKF3, the built-in models
        for i, m in enumerate(models):
            if hasattr(m, "g"):
                L.append("static const gf_ekf3_motion %s_model%d = "
                         "{gf_ekf3_motion_forward_turn, NULL, %s};"
                         % (name, i, _mat(m.R, 3, 3, single)))
            else:
                h = ("gf_ekf3_meas_x" if m.h is rec.module.meas_x
                     else "gf_ekf3_meas_xy")
                L.append("static const gf_ekf3_meas %s_model%d = {%du, %s, "
                         "NULL, %s, %du, %s};"
                         % (name, i, m.m, h, _mat(m.Q, 3, 3, single),
                            m.angle_mask, _lit(m.gate, single)))
    L.append("")
    # the models by index, for the steps
    L.append("static const void *const %s_models[%d] = {%s};" % (
        name, max(1, len(models)),
        ", ".join("&%s_model%d" % (name, i) for i in range(len(models)))
        or "NULL"))
    L.append("")
    return L


def _check(rec, name, single):
    n = rec.n
    kind = rec.kind
    L = []
    L.append("// 0 if every recorded answer is the library's, byte for "
             "byte; else 1 + the")
    L.append("// index of the first step that differs (0: the init).")
    L.append("unsigned long %s_check(void);" % name)
    L.append("unsigned long %s_check(void)" % name)
    L.append("{")
    L.append("    const unsigned long count = %du;" % len(rec.steps))
    if kind == "KF2":
        L.append("    gf_kf2 f;")
        L.append("    gf_mat2 s;")
        L.append("    gf_vec2 mu0, in;")
        L.append("    gf_innovation info;")
        L.append("    memcpy(mu0.v, %s_mu0, sizeof mu0.v);" % name)
        L.append("    memcpy(s.m, %s_sigma0, sizeof s.m);" % name)
        L.append("    if (gf_kf2_init(&f, &mu0, &s) != GF_OK) {")
    elif kind == "EKF3":
        L.append("    gf_ekf3 f;")
        L.append("    gf_mat3 s;")
        L.append("    gf_vec3 mu0, in;")
        L.append("    gf_innovation info;")
        L.append("    memcpy(mu0.v, %s_mu0, sizeof mu0.v);" % name)
        L.append("    memcpy(s.m, %s_sigma0, sizeof s.m);" % name)
        L.append("    if (gf_ekf3_init(&f, &mu0, &s) != GF_OK) {")
    else:
        L.append("    static gf_kf f;")
        L.append("    static gf_kf_work work;")
        L.append("    static gf_kf_innovation info;")
        L.append("    gf_real s[%d];" % (n * n))
        L.append("    if (gf_kf_init(&f, %du, %s_mu0, %s_sigma0, &work) != "
                 "GF_OK) {" % (n, name, name))
    L.append("        return 1;")
    L.append("    }")
    L.append("    for (unsigned long i = 0; i < count; i++) {")
    L.append("        const %s_step *t = &%s_steps[i];" % (name, name))
    L.append("        const void *model = %s_models[t->which];" % name)
    L.append("        gf_status st;")
    if kind in ("KF2", "EKF3"):
        L.append("        memcpy(in.v, t->in, sizeof in.v);")
        L.append("        memset(&info, 0, sizeof info);")
    else:
        L.append("        memset(&info, 0, sizeof info);")
    L.append("        if (t->op == 0) {")
    if kind == "KF2":
        L.append("            st = gf_kf2_predict(&f, (const gf_kf2_model *)"
                 "model, t->has_in ? &in : NULL);")
    elif kind == "EKF3":
        L.append("            st = gf_ekf3_predict(&f, (const gf_ekf3_motion "
                 "*)model, t->in);")
    else:
        L.append("            st = gf_kf_predict(&f, (const gf_kf_model *)"
                 "model, t->has_in ? t->in : NULL, &work);")
    L.append("        } else {")
    if kind == "KF2":
        L.append("            st = gf_kf2_update(&f, (const gf_kf2_meas *)"
                 "model, &in, &info);")
    elif kind == "EKF3":
        L.append("            st = gf_ekf3_update(&f, (const gf_ekf3_meas *)"
                 "model, &in, &info);")
    else:
        L.append("            st = gf_kf_update(&f, (const gf_kf_meas *)"
                 "model, t->in, &info, &work);")
    L.append("        }")
    if kind == "KF":
        L.append("        (void)gf_kf_cov(&f, s);")
        mu, sg = "f.mu", "s"
    elif kind == "KF2":
        L.append("        (void)gf_kf2_cov(&f, &s);")
        mu, sg = "f.mu.v", "s.m"
    else:
        L.append("        (void)gf_ekf3_cov(&f, &s);")
        mu, sg = "f.mu.v", "s.m"
    L.append("        int same = (int)st == t->status &&")
    L.append("                   memcmp(%s, t->mu, sizeof t->mu) == 0 &&" % mu)
    L.append("                   memcmp(%s, t->sigma, sizeof t->sigma) == 0;"
             % sg)
    L.append("        if (t->op == 1 && (st == GF_OK || st == GF_ERR_GATED)) "
             "{")
    L.append("            same = same && info.m <= %du &&" % n)
    L.append("                   memcmp(info.y, t->y, info.m * sizeof "
             "t->y[0]) == 0 &&")
    L.append("                   memcmp(&info.nis, &t->nis, sizeof t->nis) "
             "== 0;")
    L.append("        }")
    L.append("        if (!same) {")
    L.append("            return i + 2u;")
    L.append("        }")
    L.append("    }")
    L.append("    return 0;")
    L.append("}")
    L.append("")
    L.append("#ifndef GF_EXPORT_NO_MAIN")
    L.append("#include <stdio.h>")
    L.append("")
    L.append("int main(void)")
    L.append("{")
    L.append("    const unsigned long r = %s_check();" % name)
    L.append("    if (r == 0) {")
    L.append('        printf("%s: %d steps bit for bit\\n");'
             % (name, len(rec.steps)))
    L.append("        return 0;")
    L.append("    }")
    L.append("    if (r == 1) {")
    L.append('        printf("%s: the init failed\\n");' % name)
    L.append("    } else {")
    L.append('        printf("%s: step %%lu differs\\n", r - 2u);' % name)
    L.append("    }")
    L.append("    return 1;")
    L.append("}")
    L.append("#endif")
    return L
