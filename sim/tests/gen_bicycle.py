# SPDX-License-Identifier: MIT
"""The kinematic bicycle of docs/codegen.md for the node's generated-model
test (lcm_udpm.sh generated), in two commands:

    python gen_bicycle.py write ROOT DIR
        writes DIR/bicycle_model.h and .c with gaussfilt.codegen (from the
        checkout ROOT, without the package installed: only SymPy)
    python gen_bicycle.py sim LIB URL LOG --first K --runs M --steps N --seed S
        simulates M runs of the bicycle (tracks K, K+1, ...) with the
        library's own g, R, h and Q (ctypes; LIB built in double) and
        publishes them as gf_sim does (over URL, "-" for none, and into
        the LCM log LOG, the same bytes): per step of 0.1 s the control (the
        inputs of the step that ends at its utime), the truth, then the
        compass and the wheel speed; the GPS every tenth step. The
        measurements carry q of zeros: the node takes each sensor's Q from
        its configuration, here the library's.

States (x, y, theta, v, delta), inputs (acceleration, steering rate),
parameters (L, the wheelbase). The truth starts from a draw of the prior
the node's configuration gives (PRIOR_MEAN, PRIOR_COV below; the node's
dt = 0.1: the prior one step before the first control) and moves by
x' = g(x, u, dt) + w, w ~ N(0, R(dt)): the model the node runs, so its
NEES and NIS are chi-square.
"""
import ctypes
import importlib.util
import pathlib
import sys

PRIOR_MEAN = [0.0, 0.0, 0.0, 2.0, 0.0]
PRIOR_COV = [1.0, 1.0, 0.01, 0.25, 0.0004]
WHEELBASE = 2.5
DT = 0.1
SENSORS = [("compass", 1, 1), ("wheel", 1, 1), ("gps", 2, 10)]  # every k


def model(cg, sp):
    x, y, th, v, de = sp.symbols("x y theta v delta")
    a, w = sp.symbols("a steer_rate")
    L = sp.Symbol("L")
    return cg.Model(
        "bicycle",
        states=[cg.State(x, "m"), cg.State(y, "m"),
                cg.State(th, "rad", angle=True), cg.State(v, "m/s"),
                cg.State(de, "rad", angle=True)],
        inputs=[a, w], params=[L],
        motion=[x + v * sp.cos(th) * cg.dt, y + v * sp.sin(th) * cg.dt,
                th + v / L * sp.sin(de) / sp.cos(de) * cg.dt,
                v + a * cg.dt, de + w * cg.dt],
        R=sp.diag(sp.Rational(1, 100), sp.Rational(1, 100),
                  sp.Rational(1, 1000), sp.Rational(1, 10),
                  sp.Rational(1, 10000)) * cg.dt,
        sensors=[cg.Sensor("gps", [x, y], Q=sp.diag(4, 4)),
                 cg.Sensor("compass", [th],
                           Q=sp.Matrix([[sp.Rational(1, 100)]]), angles=[0]),
                 cg.Sensor("wheel", [v],
                           Q=sp.Matrix([[sp.Rational(1, 25)]]))])


def write(root, out):
    path = pathlib.Path(root) / "python" / "gaussfilt" / "codegen.py"
    spec = importlib.util.spec_from_file_location("gf_codegen", path)
    cg = importlib.util.module_from_spec(spec)
    sys.modules["gf_codegen"] = cg
    spec.loader.exec_module(cg)
    import sympy as sp
    h, c = cg.write(model(cg, sp), out)
    print(h, c)


def sim(lib_path, url, log_path, first, runs, steps, seed):
    import lcm
    import numpy as np
    from gaussfilt_lcm import control_t, groundtruth_t, measurement_t

    lib = ctypes.CDLL(str(pathlib.Path(lib_path).resolve()))
    D = ctypes.POINTER(ctypes.c_double)
    n = 5
    par = (ctypes.c_double * 1)(WHEELBASE)

    def arr(a):
        return a.ctypes.data_as(D)

    def g(x, u):
        mu = np.ascontiguousarray(x, dtype=np.float64)
        out = mu.copy()  # gf_ekf's preset: the entries g keeps
        G = np.eye(n)
        uu = np.array(list(u) + [DT])
        assert lib.bicycle_g(par, n, arr(mu), arr(uu), arr(out), arr(G)) == 0
        return out

    def R():
        r = np.zeros((n, n))
        lib.bicycle_R(par, ctypes.c_double(DT), arr(r))
        return r

    def h(name, m, x):
        mu = np.ascontiguousarray(x, dtype=np.float64)
        z = np.zeros(m)
        H = np.zeros((m, n))
        fn = getattr(lib, "bicycle_h_" + name)
        assert fn(par, n, m, arr(mu), arr(z), arr(H)) == 0
        return z

    def Q(name, m):
        q = np.zeros((m, m))
        getattr(lib, "bicycle_Q_" + name)(par, arr(q))
        return q

    lc = lcm.LCM(url) if url != "-" else None
    log = lcm.EventLog(log_path, "w", overwrite=True)
    clock = [0]

    def publish(channel, data):
        # the same bytes over LCM and into the log (event times: a step's
        # 0.1 s, increasing across runs)
        if lc is not None:
            lc.publish(channel, data)
        clock[0] += 1
        log.write_event(clock[0], channel, data)
    rng = np.random.default_rng(seed)
    Rl = np.linalg.cholesky(R())
    Ql = {s: np.linalg.cholesky(Q(s, m)) for s, m, _ in SENSORS}
    for r in range(runs):
        track = first + r
        x = np.array(PRIOR_MEAN) + rng.normal(size=n) * np.sqrt(PRIOR_COV)
        seq = 0
        sseq = {s: 0 for s, _, _ in SENSORS}
        for k in range(1, steps + 1):
            t = k * int(DT * 1e6)
            u = [0.2 * np.sin(0.05 * k), 0.02 * np.cos(0.07 * k)]
            x = g(x, u) + Rl @ rng.normal(size=n)
            # the filter keeps its angles in (-pi, pi] and scripts/nees
            # takes a linear track's errors as they are: the drive stays
            # away from the wrap
            assert abs(x[2]) < 3.0 and abs(x[4]) < 1.0, (track, k, x)
            seq += 1
            c = control_t()
            c.utime, c.seq, c.session, c.track = t, seq, 1, track
            c.model, c.n, c.u = measurement_t.MODEL_LINEAR, 2, u
            publish("GF_CTRL_%d" % track, c.encode())
            gt = groundtruth_t()
            gt.utime, gt.seq, gt.track = t, seq, track
            gt.model, gt.n, gt.state = measurement_t.MODEL_LINEAR, n, list(x)
            publish("GF_TRUTH_%d" % track, gt.encode())
            for s, m, every in SENSORS:
                if k % every != 0:
                    continue
                z = h(s, m, x) + Ql[s] @ rng.normal(size=m)
                sseq[s] += 1
                msg = measurement_t()
                msg.utime, msg.seq, msg.session = t, sseq[s], 1
                msg.track, msg.model, msg.m = track, measurement_t.MODEL_LINEAR, m
                msg.z = list(z)
                msg.q = [[0.0] * m for _ in range(m)]  # the sensor's Q
                publish("GF_MEAS_%d_%s" % (track, s), msg.encode())
    log.close()
    print("gen_bicycle: %d runs of %d steps on tracks %d..%d (%s, %s)"
          % (runs, steps, first, first + runs - 1, url, log_path))


def main(argv):
    if argv[1] == "write":
        write(argv[2], argv[3])
        return 0
    opts = dict(zip(argv[5::2], argv[6::2]))
    sim(argv[2], argv[3], argv[4], int(opts["--first"]), int(opts["--runs"]),
        int(opts["--steps"]), int(opts["--seed"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
