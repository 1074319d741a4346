# SPDX-License-Identifier: MIT
"""gaussfilt.codegen: the generated C compiles warning-free under the
strict flags with gcc and clang in both precisions and for the
Cortex-M4F; its values and Jacobians (run through ctypes) agree with
central differences of the SymPy model in 50-digit arithmetic (mpmath)
to 1e-7 relative in double, on the bicycle and on a seeded family of
random models (products, quotients, sin and cos of states, square roots
of sums of squares); a filter stepped with them runs; and models that
cannot be C (an unsupported function, a dimension mismatch, a name that
clashes with C) are refused with a message naming the cause.
"""
import ctypes
import math
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

sp = pytest.importorskip("sympy")
mpmath = pytest.importorskip("mpmath")

import gaussfilt  # noqa: E402
from gaussfilt import codegen as cg  # noqa: E402
from conftest import (BUILD, ROOT,  # noqa: E402
                      need_firmware_tools)

STRICT = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wpedantic",
          "-Wdouble-promotion", "-Wconversion", "-Werror"]


def bicycle():
    x, y, th, v, de = sp.symbols("x y theta v delta")
    a, w = sp.symbols("a steer_rate")
    L, lx, ly = sp.symbols("L lx ly")
    return cg.Model(
        "bicycle",
        states=[cg.State(x, "m"), cg.State(y, "m"),
                cg.State(th, "rad", angle=True), cg.State(v, "m/s"),
                cg.State(de, "rad", angle=True)],
        inputs=[a, w], params=[L, lx, ly],
        motion=[x + v * sp.cos(th) * cg.dt, y + v * sp.sin(th) * cg.dt,
                th + v / L * sp.sin(de) / sp.cos(de) * cg.dt,
                v + a * cg.dt, de + w * cg.dt],
        R=sp.diag(sp.Rational(1, 100), sp.Rational(1, 100),
                  sp.Rational(1, 1000), sp.Rational(1, 10),
                  sp.Rational(1, 100)) * cg.dt,
        sensors=[cg.Sensor("gps", [x, y], Q=sp.diag(4, 4)),
                 cg.Sensor("compass", [th], Q=sp.Matrix([[sp.Rational(1, 100)]]),
                           angles=[0]),
                 cg.Sensor("wheel", [v], Q=sp.Matrix([[sp.Rational(1, 25)]])),
                 cg.Sensor("range", [sp.sqrt((lx - x) ** 2 + (ly - y) ** 2)],
                           Q=sp.Matrix([[1]]))],
        source="python/tests/test_codegen.py")


def compile_strict(c, out, cc, extra=()):
    cmd = [cc] + STRICT + list(extra) + ["-I", str(ROOT / "include"), "-c",
                                         str(c), "-o", str(out)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


@pytest.mark.parametrize("prec", ["double", "float"])
@pytest.mark.parametrize("cc", ["gcc", "clang"])
def test_the_c_compiles_under_the_strict_flags(tmp_path, cc, prec):
    if shutil.which(cc) is None:
        pytest.skip("no " + cc)
    h, c = cg.write(bicycle(), tmp_path)
    text = c.read_text()
    assert text.startswith("// SPDX-License-Identifier: MIT\n")
    assert "do not edit" in text and "malloc" not in text
    assert "Operations per call" in h.read_text()
    # nothing but + - * /, GF_SQRT and gf_sincos: no libm call in the code
    code = "\n".join(ln.split("//")[0] for ln in text.splitlines())
    code = re.sub(r'"[^"]*"', '""', code)
    calls = set(re.findall(r"\b([A-Za-z_0-9]+)\(", code))
    assert calls <= {"GF_R", "GF_SQRT", "gf_sincos", "sizeof", "bicycle_g",
                     "bicycle_R", "bicycle_model", "bicycle_Q_gps",
                     "bicycle_Q_compass", "bicycle_Q_wheel", "bicycle_Q_range",
                     "bicycle_h_gps", "bicycle_h_compass", "bicycle_h_wheel",
                     "bicycle_h_range"}, calls
    compile_strict(c, tmp_path / "m.o", cc,
                   ["-DGF_SINGLE_PRECISION"] if prec == "float" else [])
    # with the descriptor exported under its fixed name (gf_node loads it)
    compile_strict(c, tmp_path / "e.o", cc, ["-DGF_CODEGEN_EXPORT"] + (
        ["-DGF_SINGLE_PRECISION"] if prec == "float" else []))


def test_the_c_compiles_for_the_cortex_m4f(tmp_path):
    need_firmware_tools("arm-none-eabi-gcc")
    _, c = cg.write(bicycle(), tmp_path)
    compile_strict(c, tmp_path / "m.o", "arm-none-eabi-gcc",
                   ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard",
                    "-mfpu=fpv4-sp-d16", "-DGF_SINGLE_PRECISION"])


def reference(exprs, syms, point, subs):
    """Values and central-difference Jacobians of exprs at point, in
    50-digit arithmetic."""
    mpmath.mp.dps = 50
    fs = [sp.lambdify(syms, e.subs(subs), modules="mpmath") for e in exprs]
    p = [mpmath.mpf(float(v)) for v in point]
    vals = [f(*p) for f in fs]
    J = []
    for f in fs:
        row = []
        for j in range(len(p)):
            h = mpmath.mpf("1e-20") * max(1, abs(p[j]))
            a, b = list(p), list(p)
            a[j] += h
            b[j] -= h
            row.append((f(*a) - f(*b)) / (2 * h))
        J.append(row)
    return vals, J


def agree(got, want, tol=1e-7):
    """|got - want| <= tol max(|want|, the row's largest |want|)."""
    got = np.asarray(got, dtype=float)
    want = np.array([[float(v) for v in r] for r in want]) if np.ndim(
        want) == 2 or isinstance(want[0], list) else np.array(
        [float(v) for v in want])
    scale = np.maximum(np.abs(want), np.max(np.abs(want), axis=-1,
                                            keepdims=True) * 1e-3 + 1e-300)
    return float(np.max(np.abs(got - want) / scale))


def test_the_bicycle_matches_its_model_in_50_digits(tmp_path):
    model = bicycle()
    b = cg.build(model, tmp_path, ROOT)
    b.set_params(L=2.5, lx=10, ly=5)
    subs = {sp.Symbol("L"): 2.5, sp.Symbol("lx"): 10, sp.Symbol("ly"): 5}
    xs = [s.symbol for s in model.states]
    rng = np.random.default_rng(5)
    worst = 0.0
    for _ in range(50):
        mu = rng.uniform(-3, 3, 5)
        u = np.array([rng.normal(), rng.normal(), 0.1])
        sub = dict(subs)
        sub.update({model.inputs[0]: u[0], model.inputs[1]: u[1], cg.dt: 0.1})
        vals, J = reference([sp.sympify(e) for e in model.motion], xs, mu, sub)
        got, G = b.g(mu, u)
        worst = max(worst, agree(got, vals), agree(G, J))
        for s in model.sensors:
            vals, J = reference([sp.sympify(e) for e in s.h], xs, mu, subs)
            z, H = b.h[s.name](mu)
            worst = max(worst, agree(z, vals), agree(H, J))
    print("bicycle: worst relative error %.3g" % worst)
    assert worst <= 1e-7


def random_model(rng, k):
    xs = sp.symbols("x0:4")
    c = [sp.Float(round(v, 3)) for v in rng.uniform(0.5, 2, 6)]
    i = rng.permutation(4)
    a, b, d, e = (xs[j] for j in i)
    forms = [a * b * c[0] + d / (e * e + c[1]),
             c[2] * sp.sin(a) * sp.cos(b) + sp.cos(d * c[3]),
             sp.sqrt(a * a + b * b + c[4]) * d,
             (a - c[5] * b) / sp.sqrt(d * d + e * e + 1),
             sp.sin(a + b) / (c[0] + sp.cos(d) * sp.cos(d))]
    h = [forms[(k + t) % len(forms)] for t in range(3)]
    model = cg.Model("fam%d" % k, states=[cg.State(x) for x in xs],
                     motion=list(xs), R=sp.eye(4),
                     sensors=[cg.Sensor("s", h, Q=sp.eye(3))])
    return model, xs, h


def test_a_family_of_random_models_in_50_digits(tmp_path):
    rng = np.random.default_rng(11)
    worst = 0.0
    for k in range(12):
        model, xs, h = random_model(rng, k)
        b = cg.build(model, tmp_path, ROOT)
        for _ in range(10):
            mu = rng.uniform(-2, 2, 4)
            vals, J = reference(h, xs, mu, {})
            z, H = b.h["s"](mu)
            worst = max(worst, agree(z, vals), agree(H, J))
    print("12 random models x 10 points: worst relative error %.3g" % worst)
    assert worst <= 1e-7


def test_the_descriptor_can_be_read(tmp_path):
    b = cg.build(bicycle(), tmp_path, ROOT)

    class Sensor(ctypes.Structure):
        _fields_ = [("name", ctypes.c_char_p), ("m", ctypes.c_uint),
                    ("angle_mask", ctypes.c_uint),
                    ("quantities", ctypes.POINTER(ctypes.c_char_p)),
                    ("h", ctypes.c_void_p), ("Q", ctypes.c_void_p)]

    class Desc(ctypes.Structure):
        _fields_ = [("version", ctypes.c_uint), ("name", ctypes.c_char_p),
                    ("n", ctypes.c_uint), ("nu", ctypes.c_uint),
                    ("nparams", ctypes.c_uint), ("angles", ctypes.c_uint),
                    ("states", ctypes.POINTER(ctypes.c_char_p)),
                    ("units", ctypes.POINTER(ctypes.c_char_p)),
                    ("inputs", ctypes.POINTER(ctypes.c_char_p)),
                    ("params", ctypes.POINTER(ctypes.c_char_p)),
                    ("g", ctypes.c_void_p), ("R", ctypes.c_void_p),
                    ("nsensors", ctypes.c_uint),
                    ("sensors", ctypes.POINTER(Sensor))]
    fn = b._lib.bicycle_model
    fn.restype = ctypes.POINTER(Desc)
    d = fn().contents
    assert (d.version, d.name, d.n, d.nu, d.nparams, d.angles) == (
        1, b"bicycle", 5, 2, 3, 0b10100)
    assert [d.states[i] for i in range(5)] == [b"x", b"y", b"theta", b"v",
                                               b"delta"]
    assert d.units[3] == b"m/s"
    assert [(d.sensors[i].name, d.sensors[i].m, d.sensors[i].angle_mask)
            for i in range(d.nsensors)] == [(b"gps", 2, 0), (b"compass", 1, 1),
                                           (b"wheel", 1, 0), (b"range", 1, 0)]

    # the same descriptor under the fixed name a loader finds (gf_node's
    # type = generated), with the export's version and gf_real's size
    class Export(ctypes.Structure):
        _fields_ = [("version", ctypes.c_uint), ("real_size", ctypes.c_uint),
                    ("model", ctypes.POINTER(Desc))]
    ex = Export.in_dll(b._lib, "gf_codegen_exported")
    assert (ex.version, ex.real_size) == (1, 8)
    assert ctypes.addressof(ex.model.contents) == ctypes.addressof(d)


@pytest.mark.parametrize("dtype", ["float32", "float64"])
def test_a_filter_runs_on_the_generated_model(tmp_path, dtype):
    b = cg.build(bicycle(), tmp_path, ROOT, dtype=dtype)
    b.set_params(L=2.5, lx=10, ly=5)
    ekf = b._module().EKF(mu=[0, 0, 0.3, 2, 0.1], sigma=np.eye(5),
                          angles=b.angles)
    for t in range(20):
        ekf.predict(b.motion(0.1), u=[0.1, 0.0, 0.1])
        ekf.update(b.meas("gps"), z=[0.2 * t, 0.06 * t])
        ekf.update(b.meas("compass"), z=[0.3])
    assert np.all(np.isfinite(ekf.mu)) and np.all(np.linalg.eigvalsh(
        ekf.sigma.astype(float)) > 0)
    # the generated Jacobians pass the library's own check
    assert gaussfilt.check_jacobians(b.meas("range"), mu=ekf.mu).worst < (
        1e-2 if dtype == "float32" else 1e-8)


def test_bad_models_are_refused():
    x, y = sp.symbols("x y")
    ok = dict(states=[cg.State(x), cg.State(y)], motion=[x, y], R=sp.eye(2),
              sensors=[cg.Sensor("s", [x], Q=sp.eye(1))])

    def refused(match, **change):
        kw = dict(ok)
        kw.update(change)
        with pytest.raises(cg.CodegenError, match=match):
            cg.generate(cg.Model("m", **kw))
    refused("tan is not one of", sensors=[cg.Sensor("s", [sp.tan(x)],
                                                    Q=sp.eye(1))])
    refused("exp is not one of", motion=[sp.exp(x), y])
    refused("a power other", sensors=[cg.Sensor("s", [x ** sp.Rational(1, 3)],
                                                Q=sp.eye(1))])
    refused("2 expressions for 3 states",
            states=[cg.State(x), cg.State(y), cg.State("w")])
    refused("Q is 2 x 2, not 1 x 1", sensors=[cg.Sensor("s", [x],
                                                        Q=sp.eye(2))])
    refused("R is 3 x 3", R=sp.eye(3))
    refused("clashes", states=[cg.State("int"), cg.State(y)],
            motion=[sp.Symbol("int"), y])
    refused("not a state, input", motion=[x + sp.Symbol("q"), y])
    with pytest.raises(cg.CodegenError, match="clashes"):
        cg.generate(cg.Model("double", **ok))
    # routed through a function of the caller's, the model is written
    kw = dict(ok)
    kw["sensors"] = [cg.Sensor("s", [sp.atan2(y, x)], Q=sp.eye(1))]
    _, src = cg.generate(cg.Model("m", functions={"atan2": "my_atan2"}, **kw))
    assert "my_atan2(" in src


def bicycle_run(b, mod, steps=120, seed=3):
    """A seeded drive recorded for export_c: GPS at 1 in 5 steps (some
    gated), the compass and the wheel at every step, a range now and then."""
    rng = np.random.default_rng(seed)
    b.set_params(L=2.5, lx=10, ly=5)
    rec = gaussfilt.Recorder(mod.EKF, mu=[0, 0, 0.3, 2, 0.1],
                             sigma=np.diag([1, 1, 0.1, 0.5, 0.05]),
                             angles=b.angles)
    gps = b.meas("gps", gate=9.0)
    motion = b.motion(0.1)
    for t in range(steps):
        rec.predict(motion, u=[rng.normal() * 0.2, rng.normal() * 0.1, 0.1])
        readings = [(b.meas("compass"), [rec.mu[2] + rng.normal() * 0.1]),
                    (b.meas("wheel"), [rec.mu[3] + rng.normal() * 0.2])]
        if t % 5 == 0:
            far = 20 if rng.random() < 0.2 else 2
            readings.append((gps, rec.mu[:2] + rng.normal(size=2) * far))
        if t % 7 == 0:
            readings.append((b.meas("range"), [11 + rng.normal()]))
        for meas, z in readings:
            try:
                rec.update(meas, z)
            except gaussfilt.Gated:
                pass
    return rec


@pytest.mark.parametrize("dtype", ["float32", "float64"])
def test_the_bicycle_run_exports_bit_for_bit(tmp_path, dtype, no_python_step):
    b = cg.build(bicycle(), tmp_path, ROOT, dtype=dtype)
    rec = bicycle_run(b, b._module())
    assert {0, gaussfilt.Gated.status} <= {s["status"] for s in rec.steps}
    path = gaussfilt.export_c(rec, tmp_path / "bike_run.c")
    exe = tmp_path / "bike_run"
    cmd = ["gcc"] + STRICT + ["-ffp-contract=off", "-I", str(ROOT / "include"),
                              "-I", str(tmp_path), str(path),
                              str(b.source)] + [
        str(p) for p in sorted((ROOT / "src").glob("*.c"))] + [
        "-lm", "-o", str(exe)]
    if dtype == "float32":
        cmd.insert(1, "-DGF_SINGLE_PRECISION")
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([str(exe)], capture_output=True, text=True)
    assert r.stdout.strip() == "bike_run: %d steps bit for bit" % len(
        rec.steps), r.stdout


def test_the_bicycle_on_the_cortex_m4f_equals_the_python_run(tmp_path,
                                                           no_python_step):
    from conftest import run_export_on_m4f
    b = cg.build(bicycle(), tmp_path, ROOT, dtype="float32")
    rec = bicycle_run(b, b._module())
    path = gaussfilt.export_c(rec, tmp_path / "bike_run.c")
    assert run_export_on_m4f([path, b.source], "export-codegen") == \
        "bike_run: %d steps bit for bit" % len(rec.steps)


# ---- the built model's callbacks in C: no Python in the step --------------

class Wrapped:
    """A built callback hidden behind a Python function: the filter calls
    it through Python, and it calls the C through ctypes."""

    def __init__(self, fn):
        self.fn, self.rows = fn, fn.rows
        self.c_name, self.built = fn.c_name, fn.built  # for the Recorder

    def __call__(self, *args):
        return self.fn(*args)


@pytest.fixture
def no_python_step(monkeypatch):
    """Every call of a built callback through Python fails the test."""
    def refuse(self, *args):
        raise AssertionError("%s called through Python" % self.c_name)
    monkeypatch.setattr(cg._CFunction, "__call__", refuse)


@pytest.mark.parametrize("dtype", ["float32", "float64"])
def test_the_built_model_steps_in_c_to_the_bits_of_the_ctypes_path(
        tmp_path, dtype, monkeypatch):
    b = cg.build(bicycle(), tmp_path, ROOT, dtype=dtype)
    mod = b._module()
    # the same drive through Python (each g and h a ctypes call)
    slow = cg.build(bicycle(), tmp_path / "slow", ROOT, dtype=dtype)
    slow.g = Wrapped(slow.g)
    slow.h = {k: Wrapped(v) for k, v in slow.h.items()}
    want = bicycle_run(slow, mod)
    with monkeypatch.context() as m:
        m.setattr(cg._CFunction, "__call__", lambda self, *a: pytest.fail(
            "%s called through Python" % self.c_name))
        got = bicycle_run(b, mod)
    assert len(got.steps) == len(want.steps) == 120 * 3 + 24 + 18
    for s, w in zip(got.steps, want.steps):
        assert s["status"] == w["status"]
        assert s["mu"].tobytes() == w["mu"].tobytes()
        assert s["sigma"].tobytes() == w["sigma"].tobytes()
        assert s["nis"].tobytes() == w["nis"].tobytes()
    # the last update's S, K and loglik: H as the C h gave it in the step
    f, g = got.filter, want.filter
    assert f.S.tobytes() == g.S.tobytes() and f.K.tobytes() == g.K.tobytes()
    assert f.loglik == g.loglik and not math.isnan(f.loglik)


@pytest.mark.parametrize("dtype", ["float32", "float64"])
def test_a_run_of_the_built_model_equals_its_steps(tmp_path, dtype,
                                                   no_python_step):
    b = cg.build(bicycle(), tmp_path, ROOT, dtype=dtype)
    b.set_params(L=2.5, lx=10, ly=5)
    mod = b._module()
    rng = np.random.default_rng(4)
    N = 60
    u = np.column_stack([rng.normal(size=N) * 0.2, rng.normal(size=N) * 0.1,
                         np.full(N, 0.1)])
    z = np.cumsum(rng.normal(size=(N, 2)), axis=0) * 0.3
    z[::4] = np.nan  # no fix at every fourth step
    motion, gps = b.motion(0.1), b.meas("gps", gate=9.0)

    def ekf():
        return mod.EKF(mu=[0, 0, 0.3, 2, 0.1], sigma=np.eye(5),
                       angles=b.angles)
    mu, sigma, nis, status = ekf().run(motion, gps, u=u, z=z)
    one = ekf()
    for t in range(N):
        one.predict(motion, u[t])
        if not np.isnan(z[t, 0]):
            try:
                one.update(gps, z[t])
            except gaussfilt.Gated:
                assert status[t] == gaussfilt.Gated.status
        assert one.mu.tobytes() == mu[t].tobytes()
        assert one.sigma.tobytes() == sigma[t].tobytes()
    assert np.isnan(nis[::4]).all() and np.isfinite(nis[1::4]).all()


def test_a_run_of_the_built_model_releases_the_gil(tmp_path, no_python_step):
    import threading
    b = cg.build(bicycle(), tmp_path, ROOT)
    b.set_params(L=2.5, lx=10, ly=5)
    N = 200_000
    u = np.tile([0.0, 0.0, 0.01], (N, 1))
    z = np.column_stack([np.arange(N) * 0.02, np.zeros(N)])
    motion, gps = b.motion(0.01), b.meas("gps")
    alone = gaussfilt.float64.EKF(mu=[0, 0, 0, 2, 0], sigma=np.eye(5)).run(
        motion, gps, u=u, z=z)
    seen = None
    # a run takes some 0.3 s: on a busy machine this thread may not be
    # scheduled within one, so a few are tried
    for _ in range(10):
        ekf = gaussfilt.float64.EKF(mu=[0, 0, 0, 2, 0], sigma=np.eye(5))
        out = {}
        th = threading.Thread(
            target=lambda: out.update(r=ekf.run(motion, gps, u=u, z=z)))
        th.start()
        # this thread runs Python while the run is on: it has let the GIL go
        while th.is_alive() and seen is None:
            if repr(ekf).endswith(" (a run in progress)>"):
                try:
                    ekf.mu
                except RuntimeError as e:
                    seen = str(e)
        th.join()
        for a, w in zip(out["r"], alone):
            assert a.tobytes() == w.tobytes()
        if seen:
            break
    assert seen is not None and "in progress in another thread" in seen


def test_the_built_models_refuse_what_does_not_fit(tmp_path):
    b64 = cg.build(bicycle(), tmp_path / "f64", ROOT)
    b32 = cg.build(bicycle(), tmp_path / "f32", ROOT, dtype="float32")
    f64 = gaussfilt.float64
    with pytest.raises(gaussfilt.BadArgument,
                       match="g's C function bicycle_g is in float32, this "
                             "module is float64"):
        f64.EKFMotion(b32.g, np.eye(5))
    with pytest.raises(gaussfilt.BadArgument,
                       match="h's C function bicycle_h_gps is in float64, "
                             "this module is float32"):
        gaussfilt.float32.EKFMeas(b64.h["gps"], np.eye(2), 5)
    with pytest.raises(gaussfilt.BadArgument,
                       match="EKFMotion: g's C function bicycle_g is for 5 "
                             "states, R is 4 x 4"):
        f64.EKFMotion(b64.g, np.eye(4))
    with pytest.raises(gaussfilt.BadArgument,
                       match="EKFMeas: h's C function bicycle_h_gps is for 5 "
                             "states, n is 6"):
        f64.EKFMeas(b64.h["gps"], np.eye(2), 6)
    with pytest.raises(gaussfilt.BadArgument,
                       match="EKFMeas: h's C function bicycle_h_gps measures "
                             "2 quantities, Q is 1 x 1"):
        f64.EKFMeas(b64.h["gps"], np.eye(1), 5)
    with pytest.raises(gaussfilt.BadArgument,
                       match="bicycle_h_range is a measurement, not a motion"):
        f64.EKFMotion(b64.h["range"], np.eye(5))

    class Foreign:
        gf_capsule = "not a capsule"

        def __call__(self, mu, u):
            return mu, np.eye(5)
    with pytest.raises(gaussfilt.BadArgument,
                       match="g.gf_capsule is not a capsule of gaussfilt's C "
                             "functions"):
        f64.EKFMotion(Foreign(), np.eye(5))
    # u of the wrong length never reaches the C
    ekf = f64.EKF(mu=[0, 0, 0.3, 2, 0.1], sigma=np.eye(5))
    before = (ekf.mu.tobytes(), ekf.sigma.tobytes())
    with pytest.raises(gaussfilt.BadArgument,
                       match="EKF.predict: u must have 3 entries for "
                             "bicycle_g"):
        ekf.predict(b64.motion(0.1), u=[0.0, 0.1])
    with pytest.raises(gaussfilt.BadArgument,
                       match=r"EKF.run: u must have shape \(steps, 3\)"):
        ekf.run(b64.motion(0.1), u=np.zeros((4, 2)))
    # a NaN from the C at the linearisation point (the range at the
    # landmark itself: 0 / 0) is a status, the belief unchanged
    b64.set_params(L=2.5, lx=0, ly=0)
    ekf = f64.EKF(mu=[0, 0, 0.3, 2, 0.1], sigma=np.eye(5))
    with pytest.raises(gaussfilt.NonFinite):
        ekf.update(b64.meas("range"), [1.0])
    assert (ekf.mu.tobytes(), ekf.sigma.tobytes()) == before


# ---- the 8-state GPS model, generated beside examples/gps8.c's --------------

def gps8_model():
    """examples/gps8_model.py's model."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "gps8_model", ROOT / "examples" / "gps8_model.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.model()


def test_the_generated_gps8_matches_its_model_in_50_digits(tmp_path):
    model = gps8_model()
    b = cg.build(model, tmp_path, ROOT)
    rng = np.random.default_rng(8)
    xs = [s.symbol for s in model.states]
    worst = 0.0
    for _ in range(10):
        sats = rng.normal(size=(4, 3))
        sats = sats / np.linalg.norm(sats, axis=1, keepdims=True) * 2.66e7
        b.params[:] = sats.reshape(-1)
        subs = dict(zip(model.params, b.params.tolist()))
        mu = np.concatenate([rng.normal(size=3) * 4e6, rng.normal(size=3) * 20,
                             [3e4, 2.0]])
        vals, J = reference([sp.sympify(e) for e in model.sensors[0].h], xs,
                            mu, subs)
        z, H = b.h["rho"](mu)
        worst = max(worst, agree(z, vals), agree(H, J))
        sub = {cg.dt: 1.0}
        vals, J = reference([sp.sympify(e) for e in model.motion], xs, mu,
                            sub)
        got, G = b.g(mu, [1.0])
        worst = max(worst, agree(got, vals), agree(G, J))
    print("gps8: worst relative error %.3g" % worst)
    assert worst <= 1e-7


def gps8_runs(tmp_path, prec, cc="gcc"):
    """examples/gps8.c on its hand-written model and on the generated one,
    built for the host in prec; each run's --write output as an array
    (step, x, y, z, b)."""
    gen = tmp_path / "gen"
    cg.write(gps8_model(), gen)
    ex = ROOT / "examples"
    out = {}
    for name, model_c in (("hand", ex / "gps8_hand.c"),
                          ("generated", gen / "gps8_model.c")):
        exe = tmp_path / ("gps8_%s_%s" % (name, prec))
        cmd = [cc, "-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra",
               "-Werror", "-I", str(ROOT / "include"), "-I", str(ex), "-I",
               str(gen), str(ex / "gps8.c"), str(model_c)] + [
            str(p) for p in sorted((ROOT / "src").glob("*.c"))] + [
            "-lm", "-o", str(exe)]
        if prec == "float":
            cmd.insert(1, "-DGF_SINGLE_PRECISION")
        r = subprocess.run(cmd, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        traj = tmp_path / ("%s_%s.txt" % (name, prec))
        r = subprocess.run([str(exe), "--write", str(traj)],
                           capture_output=True, text=True)
        assert r.returncode == 0 and "gps8 (%s): checks passed" % prec in \
            r.stdout, r.stdout
        out[name] = np.loadtxt(traj)
    return out["hand"], out["generated"]


@pytest.mark.parametrize("prec", ["double", "float"])
def test_the_generated_gps8_gives_the_hand_written_beliefs(tmp_path, prec):
    hand, gen = gps8_runs(tmp_path, prec)
    assert hand.shape == gen.shape == (300, 5)
    assert (hand[:, 0] == gen[:, 0]).all()
    # the same filter: the callbacks differ in rounding only (H's
    # quotients through one shared reciprocal where the hand divides)
    ulp = np.spacing(np.abs(hand[:, 1:]).astype(
        np.float64 if prec == "double" else np.float32)).astype(np.float64)
    ulps = np.abs(gen[:, 1:] - hand[:, 1:]) / ulp
    same = int((gen == hand).all(axis=1).sum())
    print("gps8 (%s): generated against hand-written over 300 fixes: worst "
          "%.2f ulp (position, clock bias), %d fixes identical"
          % (prec, ulps.max(), same))
    assert ulps.max() <= 4.0


def test_the_generated_gps8_compiles_under_the_strict_flags(tmp_path):
    _, c = cg.write(gps8_model(), tmp_path)
    for cc in ("gcc", "clang"):
        if shutil.which(cc) is None:
            continue
        for extra in ([], ["-DGF_SINGLE_PRECISION"]):
            compile_strict(c, tmp_path / "m.o", cc, extra)
    if shutil.which("arm-none-eabi-gcc"):
        compile_strict(c, tmp_path / "m.o", "arm-none-eabi-gcc",
                       ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard",
                        "-mfpu=fpv4-sp-d16", "-DGF_SINGLE_PRECISION"])


def m4f_counts(sources, variant):
    """Builds examples/gps8_count.c with sources into the Cortex-M4F image
    gf_fw_export (float, -Os) and runs it under QEMU's insncount plugin
    (bench/qemu/m4f.sh's gf_m4f_count): {part: instructions per call}."""
    need_firmware_tools("arm-none-eabi-gcc", "arm-none-eabi-nm",
                        "qemu-system-arm")
    files = [ROOT / "examples" / "gps8_count.c"] + list(sources)
    r = subprocess.run(
        ["bash", "-c", '. scripts/lib.sh && . scripts/firmware.sh && '
         '. bench/qemu/m4f.sh && dir=$(GF_FW_VARIANT="$0" gf_fw_build '
         'cortex-m4f float -DGF_FW_EXPORT="$1" | tail -1) && '
         'plugin=$(gf_m4f_plugin) && '
         'gf_m4f_count "$dir/gf_fw_export.elf" "$plugin"', variant,
         ";".join(str(f) for f in files)],
        cwd=ROOT, env=dict(os.environ, GF_BUILD=str(BUILD)),
        capture_output=True, text=True, timeout=900)
    assert r.returncode == 0, r.stdout + r.stderr
    counts = {}
    for line in r.stdout.splitlines():
        f = line.split()
        if len(f) == 8 and f[0] == "gps8":
            counts[f[1]] = (float(f[3]), float(f[4]))  # insns, vdiv
    assert sorted(counts) == ["g", "h", "step"], r.stdout
    return counts


def test_the_generated_gps8_costs_no_more_on_the_cortex_m4f(tmp_path):
    gen = tmp_path / "gen"
    cg.write(gps8_model(), gen)
    hand = m4f_counts([ROOT / "examples" / "gps8_hand.c"], "gps8-hand")
    ours = m4f_counts([gen / "gps8_model.c"], "gps8-generated")
    print("gps8 on the Cortex-M4F (float, -Os), instructions per call "
          "(VDIV among them):")
    for part, what in (("g", "motion g and G"), ("h", "pseudoranges h and H"),
                       ("step", "predict + update")):
        print("  %-22s hand-written %8.0f (%2.0f)   generated %8.0f (%2.0f)"
              % ((what,) + hand[part] + ours[part]))
    for part in ("g", "h", "step"):
        assert ours[part][0] <= hand[part][0], (part, hand, ours)
