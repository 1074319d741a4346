# SPDX-License-Identifier: MIT
"""gaussfilt.codegen: an EKF model written once in SymPy, its Jacobians
derived, and C for gf_ekf written from it (optional: needs SymPy,
`pip install ./python[codegen]`).

    import sympy as sp
    from gaussfilt import codegen as cg

    x, y, th, v = sp.symbols("x y theta v")
    a, w = sp.symbols("a omega")          # inputs
    model = cg.Model(
        "unicycle",
        states=[cg.State(x, "m"), cg.State(y, "m"),
                cg.State(th, "rad", angle=True), cg.State(v, "m/s")],
        inputs=[a, w],
        motion=[x + v * sp.cos(th) * cg.dt, y + v * sp.sin(th) * cg.dt,
                th + w * cg.dt, v + a * cg.dt],
        R=sp.diag(1e-4, 1e-4, 1e-5, 1e-3) * cg.dt,
        sensors=[cg.Sensor("gps", [x, y], Q=sp.diag(4, 4))])
    cg.write(model, "out/")   # out/unicycle_model.h, out/unicycle_model.c

The C (docs/codegen.md has the whole of it): gf_ekf callbacks NAME_g (the
motion and G) and NAME_h_SENSOR (each sensor's z_hat and H), NAME_R (R at
a dt) and NAME_Q_SENSOR, straight-line code in gf_real with common
subexpressions computed once and the entries the filter presets (mu_bar's
equal to mu, G's identity, H's zeros) not written; only + - * /, GF_SQRT
and the library's gf_sincos, so that the results are the same on every
IEEE target. Any other function is refused when the C is written, unless
`functions` maps it to a C function of the caller's. A callback's u holds
the inputs, then dt; its ctx, the parameters (gf_real, in the order
given). NAME_model() returns a descriptor: n, the inputs, the parameters,
the states' names, units and angles, and each sensor's name, m, callback
and noise.
"""
import os
import pathlib
import re
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

try:
    import sympy as sp  # type: ignore[import-untyped]
except ImportError as e:  # pragma: no cover - the extra is not installed
    raise ImportError("gaussfilt.codegen needs SymPy: pip install "
                      "'gaussfilt[codegen]' (or sympy)") from e

__all__ = ["State", "Sensor", "Model", "dt", "write", "generate",
           "CodegenError"]

#: The step's length: use it in the motion and in R.
dt: Any = sp.Symbol("dt", positive=True)

_C_KEYWORDS = set("""auto break case char const continue default do double
else enum extern float for goto if inline int long register restrict return
short signed sizeof static struct switch typedef union unsigned void
volatile while _Bool _Complex _Imaginary
""".split())


class CodegenError(ValueError):
    """A model that cannot be written as C: the message says why."""


@dataclass
class State:
    """A state: its symbol (or name), unit, and whether it is an angle
    (kept in (-pi, pi] by the filter)."""
    symbol: object
    unit: str = ""
    angle: bool = False

    def __post_init__(self) -> None:
        if isinstance(self.symbol, str):
            self.symbol = sp.Symbol(self.symbol)


@dataclass
class Sensor:
    """A measurement model z = h(x): its name, the m expressions of the
    states (and parameters), Q (m x m, of the parameters), and which of its
    quantities are angles (residuals wrapped), by index."""
    name: str
    h: Sequence[object]
    Q: object
    angles: Sequence[int] = ()
    names: Optional[Sequence[str]] = None


@dataclass
class Model:
    """The motion x' = g(x, u, dt) (one expression per state), R (n x n,
    of dt and the parameters), the inputs u and parameters p (symbols),
    and the sensors."""
    name: str
    states: List[State]
    motion: Sequence[object]
    R: object
    sensors: List[Sensor]
    inputs: Sequence[object] = ()
    params: Sequence[object] = ()
    functions: Dict[str, str] = field(default_factory=dict)
    source: str = ""


# ---- checks ---------------------------------------------------------------

def _ident(name, what):
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise CodegenError("%s %r is not a C identifier" % (what, name))
    if name in _C_KEYWORDS or name.startswith("gf_") or name.startswith("GF_"):
        raise CodegenError("%s %r clashes with a C keyword or a name the "
                           "generated code uses" % (what, name))


def _check(model):
    _ident(model.name, "the model's name")
    n = len(model.states)
    if n < 1:
        raise CodegenError("the model has no states")
    if len(model.motion) != n:
        raise CodegenError("the motion has %d expressions for %d states"
                           % (len(model.motion), n))
    syms = [s.symbol for s in model.states] + list(model.inputs) + \
        list(model.params)
    names = [str(s) for s in syms]
    for s in syms:
        if not isinstance(s, sp.Symbol):
            raise CodegenError("%r is not a SymPy symbol" % (s,))
        _ident(str(s), "the symbol")
    if len(set(names)) != len(names) or "dt" in names:
        raise CodegenError("the states, inputs and parameters need distinct "
                           "names, none of them dt")
    R = sp.Matrix(model.R)
    if R.shape != (n, n):
        raise CodegenError("R is %d x %d, not %d x %d" % (R.shape + (n, n)))
    known = set(syms) | {dt}
    for e in list(model.motion) + list(R):
        _free(e, known, "the motion and R")
    if not model.sensors:
        raise CodegenError("the model has no sensors")
    seen = set()
    for s in model.sensors:
        _ident(s.name, "the sensor's name")
        if s.name in seen:
            raise CodegenError("two sensors named %r" % s.name)
        seen.add(s.name)
        m = len(s.h)
        Q = sp.Matrix(s.Q)
        if m < 1 or m > n:
            raise CodegenError("sensor %r measures %d quantities (1..n = %d)"
                               % (s.name, m, n))
        if Q.shape != (m, m):
            raise CodegenError("sensor %r: Q is %d x %d, not %d x %d"
                               % ((s.name,) + Q.shape + (m, m)))
        if any(i < 0 or i >= m for i in s.angles):
            raise CodegenError("sensor %r: angles index beyond its %d "
                               "quantities" % (s.name, m))
        if s.names is not None and len(s.names) != m:
            raise CodegenError("sensor %r: %d names for %d quantities"
                               % (s.name, len(s.names), m))
        for e in list(s.h):
            _free(e, set(syms) - set(model.inputs), "sensor %r" % s.name)
        for e in list(Q):
            _free(e, set(model.params), "sensor %r's Q" % s.name)


def _free(e, known, where):
    e = sp.sympify(e)
    extra = e.free_symbols - known
    if extra:
        raise CodegenError("%s: %s not a state, input, parameter or dt"
                           % (where, ", ".join(sorted(map(str, extra)))))


# ---- the printer ----------------------------------------------------------

class _Printer:
    """Expressions as C in gf_real: + - * /, GF_SQRT, the caller's
    functions; sin and cos come in as the symbols of a gf_sincos call."""

    def __init__(self, names, functions):
        self.names = names  # Symbol -> C expression
        self.functions = functions
        self.ops = 0

    def lit(self, r):
        r = sp.Rational(r) if not isinstance(r, sp.Float) else r
        if isinstance(r, sp.Float):
            return "GF_R(%s)" % _float(float(r))
        p, q = int(r.p), int(r.q)
        if q == 1:
            return "GF_R(%d.0)" % p
        if q & (q - 1) == 0:  # a power of two: exact as a literal
            return "GF_R(%s)" % _float(p / q)
        self.ops += 1
        return "(GF_R(%d.0) / GF_R(%d.0))" % (p, q)

    def __call__(self, e):
        if e in self.names:
            return self.names[e]
        if e.is_Number:
            if e.is_Rational or e.is_Float:
                return self.lit(e)
            raise CodegenError("the number %s is not real" % e)
        if e.is_NumberSymbol:
            return "GF_R(%s)" % _float(float(e))
        if e.is_Symbol:
            raise CodegenError("unknown symbol %s" % e)
        if e.is_Add:
            terms = list(e.args)
            out = self(terms[0])
            for t in terms[1:]:
                self.ops += 1
                c, rest = t.as_coeff_Mul()
                if c.is_Number and c < 0:
                    out += " - " + self._factor(-t)
                else:
                    out += " + " + self._factor(t)
            return "(" + out + ")"
        if e.is_Mul:
            c, rest = e.as_coeff_Mul()
            if c == -1:
                return "(-" + self._factor(rest) + ")"
            num, den = [], []
            if c.is_Rational and not c.is_Integer and c.q & (c.q - 1):
                # p/q x as (p x) / q: one rounding of the quotient
                if c.p != 1:
                    num.append(sp.Integer(c.p))
                den.append(sp.Integer(c.q))
                e = rest
            for f in (e.args if e.is_Mul else (e,)):
                b, x = f.as_base_exp()
                if x.is_Integer and x < 0:
                    den.append(b if x == -1 else b ** (-x))
                elif x.is_Rational and x < 0:
                    den.append(b ** (-x))
                else:
                    num.append(f)
            top = " * ".join(self._factor(f) for f in num) if num else \
                "GF_R(1.0)"
            self.ops += max(0, len(num) - 1)
            if not den:
                return "(" + top + ")"
            bottom = " * ".join(self._factor(f) for f in den)
            self.ops += len(den)
            return "(" + top + " / " + (bottom if len(den) == 1
                                         else "(" + bottom + ")") + ")"
        if e.is_Pow:
            b, x = e.args
            if x.is_Integer:
                k = int(x)
                if k == 0:
                    return "GF_R(1.0)"
                s = self._factor(b)
                body = " * ".join([s] * abs(k))
                self.ops += abs(k) - 1
                if k < 0:
                    self.ops += 1
                    return "(GF_R(1.0) / (" + body + "))"
                return "(" + body + ")"
            if x.is_Rational and x.q == 2:
                self.ops += 1
                root = "GF_SQRT(" + self(b) + ")"
                k = int(x.p)
                if k == 1:
                    return root
                rest = sp.Pow(b, (abs(k) - 1) // 2)
                val = root if abs(k) == 1 else \
                    "(" + root + " * " + self(rest) + ")"
                if k < 0:
                    self.ops += 1
                    return "(GF_R(1.0) / " + val + ")"
                self.ops += 1
                return val
            raise CodegenError("%s: a power other than an integer or a half "
                               "(only + - * /, sqrt, sin and cos are written)"
                               % e)
        if isinstance(e, sp.Function) or hasattr(e, "func"):
            fname = getattr(e.func, "__name__", str(e.func))
            if fname in self.functions:
                self.ops += 1
                return "%s(%s)" % (self.functions[fname],
                                   ", ".join(self(a) for a in e.args))
            raise CodegenError(
                "%s: %s is not one of + - * /, sqrt, sin, cos; pass "
                "functions={%r: 'your_c_function'} to route it to a C "
                "function of yours (its results are then your C library's)"
                % (e, fname, fname))
        raise CodegenError("cannot write %s as C" % e)

    def _factor(self, e):
        return self(e)


def _float(v):
    s = repr(float(v))
    if "e" not in s and "." not in s and "inf" not in s and "nan" not in s:
        s += ".0"
    if s in ("inf", "-inf", "nan"):
        raise CodegenError("a constant is not finite")
    return s


# ---- one callback's body ----------------------------------------------------

def _body(outputs, names, functions, indent="    "):
    """C statements computing outputs [(lhs, expr, comment)] with sin and
    cos through gf_sincos and common subexpressions once; returns (lines,
    operation count)."""
    exprs = [sp.sympify(e) for _, e, _ in outputs]
    # sin(a) and cos(a) of each argument a: one gf_sincos, innermost first
    trig = {}
    lines = []
    pr = _Printer(dict(names), functions)
    k = 0
    while True:
        atoms = set()
        for e in exprs:
            atoms |= {f for f in e.atoms(sp.sin, sp.cos)}
        if not atoms:
            break
        inner = [f for f in atoms if not f.args[0].atoms(sp.sin, sp.cos)]
        args = sorted({f.args[0] for f in inner}, key=sp.default_sort_key)
        sub = {}
        for a in args:
            s, c = sp.Symbol("s%d_" % k), sp.Symbol("c%d_" % k)
            trig[a] = (s, c)
            pr.names[s] = "s%d" % k
            pr.names[c] = "c%d" % k
            lines.append("%sgf_real s%d, c%d; // sin, cos of %s"
                         % (indent, k, k, sp.sstr(a)))
            lines.append("%sgf_sincos(%s, &s%d, &c%d);"
                         % (indent, pr(a), k, k))
            pr.ops += 1
            sub[sp.sin(a)] = s
            sub[sp.cos(a)] = c
            k += 1
        exprs = [e.xreplace(sub) for e in exprs]
    temps, reduced = _inline(*sp.cse(exprs,
                                     symbols=sp.numbered_symbols("t_"),
                                     optimizations="basic",
                                     order="canonical"))
    for i, (t, e) in enumerate(temps):
        pr.names[t] = "t%d" % i
        lines.append("%sconst gf_real t%d = %s;" % (indent, i, _strip(pr(e))))
    for (lhs, _, comment), e in zip(outputs, reduced):
        lines.append("%s// %s" % (indent, comment))
        lines.append("%s%s = %s;" % (indent, lhs, _strip(pr(e))))
    return lines, pr.ops


def _inline(temps, reduced):
    """Puts back where they are used the temporaries that are the negation
    of a symbol (-a): b + (-a) is written b - a, one operation where the
    temporary costs two, and a product with it a negated product (one
    instruction on most FPUs, VNMUL on the M4F)."""
    kept, sub = [], {}
    for t, e in temps:
        e = e.xreplace(sub)
        if e.is_Mul and len(e.args) == 2 and e.args[0] == -1 and \
                e.args[1].is_Symbol:
            sub[t] = e
        else:
            kept.append((t, e))
    return kept, [e.xreplace(sub) for e in reduced]


def _strip(s):
    """Drop one pair of outer parentheses."""
    if s.startswith("(") and s.endswith(")"):
        depth = 0
        for i, ch in enumerate(s):
            depth += ch == "("
            depth -= ch == ")"
            if depth == 0 and i < len(s) - 1:
                return s
        return s[1:-1]
    return s


# ---- the files ----------------------------------------------------------------

def generate(model: Model) -> Tuple[str, str]:
    """The header and the source for `model`, as two strings."""
    _check(model)
    name = model.name
    N = name.upper()
    n = len(model.states)
    xs = [s.symbol for s in model.states]
    nu = len(model.inputs)
    npar = len(model.params)
    names = {x: "mu[%d]" % i for i, x in enumerate(xs)}
    names.update({u: "u[%d]" % i for i, u in enumerate(model.inputs)})
    names[dt] = "u[%d]" % nu
    names.update({p: "p[%d]" % i for i, p in enumerate(model.params)})
    g = [sp.sympify(e) for e in model.motion]
    G = sp.Matrix(g).jacobian(xs)
    angles = sum(1 << i for i, s in enumerate(model.states) if s.angle)
    origin = model.source or "a Model in Python"
    ops_total = {}

    # motion: mu_bar's entries other than the state's own (gf_ekf presets
    # mu_bar to mu) and G's other than the identity's
    outs = [("mu_bar[%d]" % i, g[i], "%s' = %s" % (xs[i], sp.sstr(g[i])))
            for i in range(n) if g[i] != xs[i]]
    for i in range(n):
        for j in range(n):
            e = G[i, j]
            if e == (1 if i == j else 0):
                continue
            outs.append(("G[%d]" % (i * n + j), e, "G[%d][%d] = d %s' / d %s "
                         "= %s" % (i, j, xs[i], xs[j], sp.sstr(e))))
    g_lines, ops_total["g"] = _body(outs, names, model.functions)
    R = sp.Matrix(model.R)
    r_outs = [("R[%d]" % (i * n + j), R[i, j], "R[%d][%d] = %s"
               % (i, j, sp.sstr(R[i, j])))
              for i in range(n) for j in range(n)]
    r_names = dict(names)
    r_names[dt] = "dt"
    r_lines, ops_total["R"] = _body(r_outs, r_names, model.functions)

    sensors = []
    for s in model.sensors:
        h = [sp.sympify(e) for e in s.h]
        m = len(h)
        H = sp.Matrix(h).jacobian(xs)
        outs = [("z[%d]" % i, h[i], "z[%d] = %s" % (i, sp.sstr(h[i])))
                for i in range(m)]
        for i in range(m):
            for j in range(n):
                e = H[i, j]
                if e == 0:
                    continue
                outs.append(("H[%d]" % (i * n + j), e, "H[%d][%d] = d z%d / "
                             "d %s = %s" % (i, j, i, xs[j], sp.sstr(e))))
        lines, ops = _body(outs, names, model.functions)
        Q = sp.Matrix(s.Q)
        q_outs = [("Q[%d]" % (i * m + j), Q[i, j], "Q[%d][%d] = %s"
                   % (i, j, sp.sstr(Q[i, j])))
                  for i in range(m) for j in range(m)]
        q_lines, _ = _body(q_outs, names, model.functions)
        mask = sum(1 << i for i in s.angles)
        qnames = list(s.names) if s.names is not None else \
            [str(e) if e.is_Symbol else "%s%d" % (s.name, i)
             for i, e in enumerate(h)]
        sensors.append((s.name, m, lines, ops, q_lines, mask, qnames))
        ops_total["h_" + s.name] = ops

    hdr = _header(model, N, n, nu, npar, angles, sensors, ops_total, origin)
    src = _source(model, N, n, nu, npar, angles, sensors, g_lines, r_lines,
                  origin)
    return hdr, src


def _header(model, N, n, nu, npar, angles, sensors, ops, origin):
    name = model.name
    L = ["// SPDX-License-Identifier: MIT",
         "// Generated by gaussfilt.codegen from %s; do not edit." % origin,
         "// %s: an EKF model of %d states for gf_ekf (gaussfilt/ekf.h)."
         % (name, n),
         "// Operations per call (+ - * /, sqrt, sincos): g and G %d, R %d, "
         % (ops["g"], ops["R"]) + ", ".join("h_%s %d" % (s[0], ops["h_" + s[0]])
                                           for s in sensors) + ".",
         "// States: " + ", ".join(
             "%s (%s%s)" % (s.symbol, s.unit or "-", ", angle" if s.angle
                           else "") for s in model.states) + ".",
         "// The callbacks' u: the inputs (%s), then dt; their ctx: the "
         "parameters" % (", ".join(map(str, model.inputs)) or "none"),
         "// (%s), a const gf_real array, or NULL if there are none."
         % (", ".join(map(str, model.params)) or "none"),
         "#ifndef %s_MODEL_H" % N,
         "#define %s_MODEL_H" % N,
         "",
         "#include \"gaussfilt/codegen.h\"",
         "#include \"gaussfilt/gaussfilt.h\"",
         "",
         "#ifdef __cplusplus",
         "extern \"C\" {",
         "#endif",
         "",
         "#define %s_N %du      // states" % (N, n),
         "#define %s_NU %du     // inputs (u has %s_NU + 1 entries: then dt)"
         % (N, nu, N),
         "#define %s_NPARAMS %du // parameters" % (N, npar),
         "#define %s_ANGLES %uu // the states that are angles (gf_ekf_init)"
         % (N, angles),
         "",
         "// The motion: mu_bar = g(mu, u, dt) and G = dg/dx (gf_ekf_motion_fn;",
         "// the entries it does not write are gf_ekf's presets, mu and I).",
         "gf_status %s_g(void *ctx, unsigned n, const gf_real *mu, "
         "const gf_real *u," % name,
         " " * len("gf_status %s_g(" % name) + "gf_real *mu_bar, gf_real *G);",
         "// R (n x n, row-major) for a step of dt.",
         "void %s_R(const gf_real *params, gf_real dt, gf_real *R);" % name]
    for s in sensors:
        L.append("// Sensor %s, m = %d (%s): z_hat = h(mu) and H = dh/dx."
                 % (s[0], s[1], ", ".join(s[6])))
        L.append("gf_status %s_h_%s(void *ctx, unsigned n, unsigned m, "
                 "const gf_real *mu," % (name, s[0]))
        L.append(" " * len("gf_status %s_h_%s(" % (name, s[0])) +
                 "gf_real *z, gf_real *H);")
        L.append("void %s_Q_%s(const gf_real *params, gf_real *Q);"
                 % (name, s[0]))
    L += ["// The descriptor.",
          "const gf_codegen_model *%s_model(void);" % name,
          "#ifdef GF_CODEGEN_EXPORT",
          "extern const gf_codegen_export gf_codegen_exported;",
          "#endif",
          "",
          "#ifdef __cplusplus",
          "}",
          "#endif",
          "",
          "#endif",
          ""]
    return "\n".join(L)


def _source(model, N, n, nu, npar, angles, sensors, g_lines, r_lines, origin):
    name = model.name

    def uses(lines, token):
        pat = re.compile(r"(?<![A-Za-z0-9_])" + re.escape(token))
        return any(pat.search(ln) for ln in lines
                   if not ln.lstrip().startswith("//"))
    L = ["// SPDX-License-Identifier: MIT",
         "// Generated by gaussfilt.codegen from %s; do not edit." % origin,
         "#include \"%s_model.h\"" % name,
         "",
         "#include <stddef.h>",
         "",
         "gf_status %s_g(void *ctx, unsigned n, const gf_real *mu, "
         "const gf_real *u," % name,
         " " * len("gf_status %s_g(" % name) + "gf_real *mu_bar, gf_real *G)",
         "{"]
    if uses(g_lines, "p["):
        L.append("    const gf_real *p = (const gf_real *)ctx;")
    else:
        L.append("    (void)ctx;")
    if not uses(g_lines, "mu["):
        L.append("    (void)mu;")
    if n > 0 and not uses(g_lines, "u["):
        L.append("    (void)u;")
    L.append("    if (n != %du) {" % n)
    L.append("        return GF_ERR_ARG;")
    L.append("    }")
    L += g_lines
    if not uses(g_lines, "mu_bar["):
        L.append("    (void)mu_bar;")
    if not uses(g_lines, "G["):
        L.append("    (void)G;")
    L += ["    return GF_OK;", "}", "",
          "void %s_R(const gf_real *params, gf_real dt, gf_real *R)" % name,
          "{"]
    L.append("    const gf_real *p = params;" if uses(r_lines, "p[")
             else "    (void)params;")
    if not uses(r_lines, "dt"):
        L.append("    (void)dt;")
    L += r_lines + ["}", ""]
    for (sname, m, lines, _, q_lines, mask, qnames) in sensors:
        L += ["gf_status %s_h_%s(void *ctx, unsigned n, unsigned m, "
              "const gf_real *mu," % (name, sname),
              " " * len("gf_status %s_h_%s(" % (name, sname)) +
              "gf_real *z, gf_real *H)", "{"]
        L.append("    const gf_real *p = (const gf_real *)ctx;"
                 if uses(lines, "p[") else "    (void)ctx;")
        if not uses(lines, "mu["):
            L.append("    (void)mu;")
        L += ["    if (n != %du || m != %du) {" % (n, m),
              "        return GF_ERR_ARG;", "    }"]
        L += lines
        if not uses(lines, "H["):
            L.append("    (void)H;")
        L += ["    return GF_OK;", "}", "",
              "void %s_Q_%s(const gf_real *params, gf_real *Q)"
              % (name, sname), "{"]
        L.append("    const gf_real *p = params;" if uses(q_lines, "p[")
                 else "    (void)params;")
        L += q_lines + ["}", ""]

    def strs(vals):
        return "{" + ", ".join('"%s"' % v.replace('"', "'") for v in vals) \
            + "}" if vals else "{\"\"}"
    L.append("static const char *const %s_states[] = %s;"
             % (name, strs([str(s.symbol) for s in model.states])))
    L.append("static const char *const %s_units[] = %s;"
             % (name, strs([s.unit for s in model.states])))
    L.append("static const char *const %s_inputs[] = %s;"
             % (name, strs([str(u) for u in model.inputs])))
    L.append("static const char *const %s_params[] = %s;"
             % (name, strs([str(p) for p in model.params])))
    for (sname, m, _, _, _, mask, qnames) in sensors:
        L.append("static const char *const %s_%s_quantities[] = %s;"
                 % (name, sname, strs(qnames)))
    L.append("static const gf_codegen_sensor %s_sensors[] = {" % name)
    for (sname, m, _, _, _, mask, qnames) in sensors:
        L.append("    {\"%s\", %du, %uu, %s_%s_quantities, %s_h_%s, %s_Q_%s},"
                 % (sname, m, mask, name, sname, name, sname, name, sname))
    L.append("};")
    L += ["static const gf_codegen_model %s_descriptor = {" % name,
          "    1u, \"%s\", %du, %du, %du, %uu, %s_states, %s_units, %s_inputs,"
          % (name, n, nu, npar, angles, name, name, name),
          "    %s_params, %s_g, %s_R, %du, %s_sensors};"
          % (name, name, name, len(sensors), name),
          "",
          "const gf_codegen_model *%s_model(void)" % name,
          "{",
          "    return &%s_descriptor;" % name,
          "}",
          "",
          "#ifdef GF_CODEGEN_EXPORT",
          "const gf_codegen_export gf_codegen_exported = {",
          "    GF_CODEGEN_EXPORT_VERSION, (unsigned)sizeof(gf_real), "
          "&%s_descriptor};" % name,
          "#endif",
          ""]
    return "\n".join(L)


def write(model: Model, outdir: Union[str, "os.PathLike[str]"]
          ) -> Tuple[pathlib.Path, pathlib.Path]:
    """Writes OUTDIR/NAME_model.h and NAME_model.c; returns their paths."""
    hdr, src = generate(model)
    out = pathlib.Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    h = out / ("%s_model.h" % model.name)
    c = out / ("%s_model.c" % model.name)
    h.write_text(hdr)
    c.write_text(src)
    return h, c


# ---- the model in Python, from the same C -----------------------------------

class _CFunction:
    """A generated callback: called from Python, through ctypes; given to
    EKFMotion or EKFMeas, its gf_capsule (the C function's address and the
    parameters as its ctx) lets the filter call the C directly, with no
    Python in the step. Either way the C computes, so the results are the
    firmware's bit for bit (in the build's precision)."""

    def __init__(self, built: "Built", cname: str, kind: str,
                 rows: int) -> None:
        import ctypes
        self.built = built
        self.c_name = cname
        self.kind = kind  # "g" or "h"
        self.rows = rows
        self._fn = getattr(built._lib, cname + built._suffix)
        params = built.params
        self.gf_capsule = built._ext._c_function(
            "motion" if kind == "g" else "meas", cname,
            ctypes.cast(self._fn, ctypes.c_void_p).value,
            params.ctypes.data if params.size else 0, built.n,
            built.nu + 1 if kind == "g" else rows, (built._lib, params))

    def __call__(self, mu: Any, u: Any = None) -> Tuple[Any, Any]:
        import ctypes
        import numpy as np
        b = self.built
        n = b.n
        mu = np.ascontiguousarray(mu, dtype=b.dtype).reshape(-1)
        out = np.zeros(self.rows, dtype=b.dtype)
        J = np.zeros((self.rows, n), dtype=b.dtype)
        ptr = ctypes.POINTER(b._ctype)
        if self.kind == "g":
            out[:] = mu
            J[:] = np.eye(n, dtype=b.dtype)
            uu = np.ascontiguousarray(u if u is not None else [],
                                      dtype=b.dtype).reshape(-1)
            if uu.size != b.nu + 1:
                raise ValueError("%s: u has %d entries; the model takes its "
                                 "%d inputs, then dt" % (self.c_name, uu.size,
                                                         b.nu))
            st = self._fn(b._ctx(), n, mu.ctypes.data_as(ptr),
                          uu.ctypes.data_as(ptr), out.ctypes.data_as(ptr),
                          J.ctypes.data_as(ptr))
        else:
            st = self._fn(b._ctx(), n, self.rows, mu.ctypes.data_as(ptr),
                          out.ctypes.data_as(ptr), J.ctypes.data_as(ptr))
        if st != 0:
            from ._errors import _from_status
            raise _from_status(st, "%s returned %d" % (self.c_name, st))
        return out, J


class Built:
    """A generated model compiled for the host (build()): its callbacks
    (g(mu, u) with u the inputs then dt; h[sensor](mu)), callable from
    Python and, given to gaussfilt's EKF, called by it in C; R(dt) and
    Q[sensor] in the build's precision, and the models for a step
    (motion(dt), meas(sensor))."""

    def __init__(self, model: Model, lib_path: pathlib.Path, dtype: Any,
                 header: pathlib.Path, source: pathlib.Path) -> None:
        import ctypes
        import numpy as np
        self.model = model
        self.name = model.name
        self.n = len(model.states)
        self.nu = len(model.inputs)
        self.dtype = np.dtype(dtype)
        self.header, self.source, self.library = header, source, lib_path
        self._ctype = ctypes.c_float if self.dtype == np.float32 \
            else ctypes.c_double
        self._suffix = ""
        self._lib = ctypes.CDLL(str(lib_path))
        from . import _f32, _f64
        self._ext = _f32 if self.dtype == np.float32 else _f64
        # the callbacks' ctx: this array, changed in place, never replaced
        self._params = np.zeros(len(model.params), dtype=self.dtype)
        self.angles = sum(1 << i for i, s in enumerate(model.states)
                          if s.angle)
        self.g = _CFunction(self, model.name + "_g", "g", self.n)
        self.h = {s.name: _CFunction(self, "%s_h_%s" % (model.name, s.name),
                                     "h", len(s.h))
                  for s in model.sensors}
        self.angle_masks = {s.name: sum(1 << i for i in s.angles)
                            for s in model.sensors}

    @property
    def params(self) -> Any:
        """The parameters, in the model's order (the C reads this array:
        set it in place or with set_params)."""
        return self._params

    def _ctx(self) -> Any:
        import ctypes
        if not self.params.size:
            return None
        return self.params.ctypes.data_as(ctypes.POINTER(self._ctype))

    def set_params(self, **values: float) -> None:
        """Sets parameters by name."""
        names = [str(p) for p in self.model.params]
        for k, v in values.items():
            if k not in names:
                raise KeyError("no parameter %r (the model's: %s)"
                               % (k, ", ".join(names)))
            self.params[names.index(k)] = v

    def R(self, dt: float) -> Any:
        import ctypes
        import numpy as np
        R = np.zeros((self.n, self.n), dtype=self.dtype)
        ptr = ctypes.POINTER(self._ctype)
        getattr(self._lib, self.name + "_R")(
            self._ctx(), self._ctype(dt), R.ctypes.data_as(ptr))
        return R

    def Q(self, sensor: str) -> Any:
        import ctypes
        import numpy as np
        m = self.h[sensor].rows
        Q = np.zeros((m, m), dtype=self.dtype)
        getattr(self._lib, "%s_Q_%s" % (self.name, sensor))(
            self._ctx(), Q.ctypes.data_as(ctypes.POINTER(self._ctype)))
        return Q

    def _module(self) -> Any:
        import numpy as np
        from . import float32, float64
        return float32 if self.dtype == np.float32 else float64

    def motion(self, dt: float) -> Any:
        """An EKFMotion of the generated g with R(dt)."""
        return self._module().EKFMotion(g=self.g, R=self.R(dt))

    def meas(self, sensor: str, gate: float = 0.0) -> Any:
        """An EKFMeas of sensor's generated h, its Q and angles."""
        return self._module().EKFMeas(h=self.h[sensor], Q=self.Q(sensor),
                                      n=self.n,
                                      angle_mask=self.angle_masks[sensor],
                                      gate=gate)


def build(model: Model, workdir: Union[str, "os.PathLike[str]"],
          root: Optional[Union[str, "os.PathLike[str]"]] = None,
          dtype: str = "float64", cc: str = "cc") -> "Built":
    """Writes the model's C into workdir, compiles it for the host with the
    library's angle code into a shared object in the precision asked for
    (float32 or float64), and returns a Built whose callbacks run that C.
    root: a gaussfilt checkout or vendored copy (include/ and src/); by
    default the copy the package carries (gaussfilt/c/)."""
    import os
    import pathlib
    import subprocess
    import numpy as np
    dt_ = np.dtype(dtype)
    if dt_ not in (np.float32, np.float64):
        raise CodegenError("dtype must be float32 or float64")
    base = pathlib.Path(root) if root is not None else \
        pathlib.Path(__file__).parent / "c"
    if not (base / "include" / "gaussfilt" / "gaussfilt.h").exists() or \
            not (base / "src" / "angle.c").exists():
        raise CodegenError("%s is not a gaussfilt checkout or vendored copy "
                           "(no include/gaussfilt/gaussfilt.h or src/angle.c)"
                           % base)
    h, c = write(model, workdir)
    tag = "f32" if dt_ == np.float32 else "f64"
    lib = pathlib.Path(workdir) / ("lib%s_%s.so" % (model.name, tag))
    cmd = [cc, "-std=c99", "-O2", "-ffp-contract=off", "-fPIC", "-shared",
           "-DGF_CODEGEN_EXPORT",
           "-Wall", "-Wextra", "-Werror", "-I", str(base / "include"),
           str(c), str(base / "src" / "angle.c"), "-o", str(lib)]
    if dt_ == np.float32:
        cmd.insert(1, "-DGF_SINGLE_PRECISION")
    r = subprocess.run(cmd, capture_output=True, text=True,
                       env=dict(os.environ))
    if r.returncode != 0:
        raise CodegenError("compiling the generated model failed:\n%s\n%s"
                           % (" ".join(cmd), r.stderr))
    return Built(model, lib, dt_, h, c)
