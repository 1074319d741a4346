# SPDX-License-Identifier: MIT
"""The kinematic bicycle of docs/codegen.md for the node's generated-model
test (lcm_udpm.sh generated), in three commands:

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
    python gen_bicycle.py same ROOT WORKDIR INPUTS BELIEFS [--q-ulp SENSOR]
        replays the log INPUTS into gaussfilt.float64.EKF on the callables
        of codegen.build (ROOT's C built in WORKDIR; the package installed)
        as the node steps a generated track, and compares the mean and
        covariance of every belief in the node's log BELIEFS with it, byte
        for byte: exit 0 when all are equal, 1 naming the first that is
        not (--q-ulp: that sensor's Q one ulp up in the replay; sensors'
        gates: --gate-SENSOR G, 0 by default as in the node)

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


def same(root, workdir, inputs, beliefs, gate, ulp_sensor=None):
    """Replays the inputs log into gaussfilt.float64.EKF on codegen.build's
    callables (the same generated C, stepped by the package's C) as the
    node steps a generated track, and compares every belief of the node's
    log with it, byte for byte; ulp_sensor: that sensor's Q one ulp up in
    the replay (the check must then fail)."""
    import lcm
    import numpy as np
    import sympy as sp
    from gaussfilt import codegen as cg
    from gaussfilt import float64 as gf
    from gaussfilt_lcm import belief_t, control_t, measurement_t

    built = cg.build(model(cg, sp), workdir, root=root)
    built.set_params(L=WHEELBASE)
    n, nu = built.n, built.nu
    Q = {s: built.Q(s) for s, _, _ in SENSORS}
    if ulp_sensor is not None:
        Q[ulp_sensor] = Q[ulp_sensor].copy()
        Q[ulp_sensor][0, 0] = np.nextafter(Q[ulp_sensor][0, 0], np.inf)
    meas = {s: gf.EKFMeas(h=built.h[s], Q=Q[s], n=n,
                          angle_mask=built.angle_masks[s], gate=gate[s])
            for s in Q}
    # the node's rule for a generated track (sim/node_core.c): its first
    # input predicts over the configured dt, any other over the time since
    # the last (utime difference / 1e6); a control predicts with its
    # inputs, a measurement first (when dt > 0) with inputs of zeros, then
    # updates with its sensor's h, Q and gate; the belief is published
    # after each
    tracks = {}
    for e in lcm.EventLog(inputs, "r"):
        if e.channel.startswith("GF_CTRL_"):
            c = control_t.decode(e.data)
            tracks.setdefault(c.track, []).append(
                (c.utime, c.seq, None, list(c.u)))
        elif e.channel.startswith("GF_MEAS_"):
            z = measurement_t.decode(e.data)
            assert not np.any(z.q), "a measurement with its own q"
            sensor = e.channel.split("_", 3)[3]
            tracks.setdefault(z.track, []).append(
                (z.utime, z.seq, sensor, list(z.z)))
    got = {}
    for e in lcm.EventLog(beliefs, "r"):
        if e.channel.startswith("GF_BELIEF_"):
            b = belief_t.decode(e.data)
            got.setdefault(b.track, []).append(b)

    def hexed(a):
        return np.ascontiguousarray(a, dtype="<f8").tobytes().hex()

    compared = 0
    for track in sorted(tracks):
        ins, bs = tracks[track], got.get(track, [])
        assert len(bs) == len(ins) + 1, (track, len(bs), len(ins))
        f = gf.EKF(np.array(PRIOR_MEAN), np.diag(PRIOR_COV),
                   angles=built.angles)
        time = None
        for k, b in enumerate(bs):
            if k > 0:
                utime, seq, sensor, v = ins[k - 1]
                dt = DT if time is None else (utime - time) / 1e6
                time = utime
                if sensor is None:
                    f.predict(built.motion(dt), v + [dt])
                else:
                    if dt > 0.0:
                        f.predict(built.motion(dt), [0.0] * nu + [dt])
                    f.update(meas[sensor], v)
                want = (utime, seq, sensor or "",
                        belief_t.STAGE_PREDICT if sensor is None
                        else belief_t.STAGE_UPDATE)
                have = (b.utime, b.input_seq, b.sensor, b.stage)
                assert have == want, (track, k, have, want)
            assert b.status == 0 and b.n == n, (track, k, b.status, b.n)
            for what, mine, node in (
                    ("mean", f.mu, np.array(b.mean)),
                    ("covariance", f.sigma,
                     np.array([list(r) for r in b.cov]))):
                if hexed(mine) != hexed(node):
                    d = np.flatnonzero(np.ascontiguousarray(mine).ravel() !=
                                       node.ravel())[0]
                    print("gen_bicycle: track %d, belief %d (utime %d, %s): "
                          "the %s differs first at entry %d: node %s (%r), "
                          "EKF %s (%r)"
                          % (track, b.seq, b.utime, b.sensor or "control",
                             what, d, node.ravel()[d].hex(),
                             node.ravel()[d],
                             np.ascontiguousarray(mine).ravel()[d].hex(),
                             np.ascontiguousarray(mine).ravel()[d]))
                    return 1
            compared += 1
    print("gen_bicycle: %d beliefs of %d tracks: the node's means and "
          "covariances are gaussfilt.float64.EKF's, byte for byte"
          % (compared, len(tracks)))
    return 0


def main(argv):
    if argv[1] == "write":
        write(argv[2], argv[3])
        return 0
    if argv[1] == "same":
        opts = dict(zip(argv[6::2], argv[7::2]))
        gate = {s: float(opts.get("--gate-" + s, 0.0)) for s, _, _ in SENSORS}
        return same(argv[2], argv[3], argv[4], argv[5], gate,
                    opts.get("--q-ulp"))
    opts = dict(zip(argv[5::2], argv[6::2]))
    sim(argv[2], argv[3], argv[4], int(opts["--first"]), int(opts["--runs"]),
        int(opts["--steps"]), int(opts["--seed"]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
