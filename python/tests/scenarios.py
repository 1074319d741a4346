# SPDX-License-Identifier: MIT
"""Seeded random scenarios, run two ways: written as the file that
replay/replay.c reads (the C library alone, on the host or the
Cortex-M4F), and run through the Python package. Both give the same
records, byte for byte, when the arithmetic is the same (test_bitexact.py).

A scenario is a list of operations (code, fields); the codes and the
record layout are replay.c's. The any-size EKF's models, cubic and
bilinear, are replay.c's too, written here operation for operation in the
filter's precision.
"""
import struct

import numpy as np

import gaussfilt

OP_END, OP_KF2_INIT, OP_KF2_PREDICT, OP_KF2_UPDATE = 0, 1, 2, 3
OP_KF_INIT, OP_KF_PREDICT, OP_KF_UPDATE = 4, 5, 6
OP_EKF3_INIT, OP_EKF3_PREDICT, OP_EKF3_UPDATE = 7, 8, 9
OP_EKF_INIT, OP_EKF_PREDICT, OP_EKF_UPDATE = 10, 11, 12
UPDATES = (OP_KF2_UPDATE, OP_KF_UPDATE, OP_EKF3_UPDATE, OP_EKF_UPDATE)

# The families and sizes the tests run: (family, n).
FAMILIES = [("kf2", 2), ("kf", 2), ("kf", 3), ("ekf3", 3), ("ekf", 3),
            ("kf", 4), ("ekf", 4), ("kf", 8), ("ekf", 8)]


# ---- the any-size EKF's test models (replay.c's cubic and bilinear) ------

def cubic(dt):
    """g: mu_bar_i = mu_i + DT mu_j - K3 mu_i^3 + u_i, j = i + 1 mod n."""
    DT, K3, K3X3, ONE = dt.type(0.1), dt.type(0.01), dt.type(0.03), dt.type(1)

    def g(mu, u):
        n = mu.shape[0]
        mb = np.empty(n, dt)
        G = np.eye(n, dtype=dt)
        for i in range(n):
            j = (i + 1) % n
            mb[i] = mu[i] + DT * mu[j] - K3 * mu[i] * mu[i] * mu[i] + u[i]
            G[i, i] = ONE - K3X3 * mu[i] * mu[i]
            G[i, j] = DT
        return mb, G
    return g


def bilinear(dt, m):
    """h: z_k = mu_k + HALF mu_k mu_j, j = k + 1 mod n (k < m)."""
    HALF, ONE = dt.type(0.5), dt.type(1)

    def h(mu):
        n = mu.shape[0]
        z = np.empty(m, dt)
        H = np.zeros((m, n), dt)
        for k in range(m):
            j = (k + 1) % n
            z[k] = mu[k] + HALF * mu[k] * mu[j]
            H[k, k] = ONE + HALF * mu[j]
            H[k, j] = HALF * mu[k]
        return z, H
    return h


# ---- generating ------------------------------------------------------------

def _psd(rng, n, rank=None, scale=1.0):
    L = rng.normal(size=(n, rank or n)) * scale
    return L @ L.T


def _gate(rng):
    return 0.0 if rng.random() < 0.5 else float(rng.choice([4.0, 9.0, 25.0]))


def generate(family, n, seed, steps=30):
    """The operations of one scenario (numbers in float64; rounded to the
    precision when written and when given to the package)."""
    rng = np.random.default_rng([seed, n, len(family)])
    ops = []
    mu = rng.normal(size=n)
    sigma = _psd(rng, n, scale=0.5)
    if family == "kf2":
        ops.append((OP_KF2_INIT, dict(mu=mu, sigma=sigma)))
    elif family == "kf":
        ops.append((OP_KF_INIT, dict(n=n, mu=mu, sigma=sigma)))
    elif family == "ekf3":
        mu[2] = rng.uniform(-np.pi, np.pi)
        ops.append((OP_EKF3_INIT, dict(mu=mu, sigma=sigma)))
    else:
        ops.append((OP_EKF_INIT, dict(n=n, angles=0, mu=mu * 0.5,
                                      sigma=sigma * 0.1)))
        # the any-size EKF measures a simulated truth (its models are
        # nonlinear: random readings would drive it off to infinity)
        g, truth = cubic(np.dtype(np.float64)), mu * 0.5
    for _ in range(steps):
        # a singular R now and then (rank n - 1): semidefinite is allowed
        rank = n - 1 if (n > 1 and rng.random() < 0.2) else n
        R = _psd(rng, n, rank=rank, scale=0.1)
        if family in ("kf2", "kf"):
            A = np.eye(n) + rng.normal(size=(n, n)) * 0.2
            nu = 2 if family == "kf2" else int(rng.integers(0, n + 1))
            B = rng.normal(size=(n, nu))
            c = rng.normal(size=n) * 0.1
            has_c = family == "kf2" or bool(rng.random() < 0.5)
            u = rng.normal(size=nu) if (nu and rng.random() < 0.7) else None
            if family == "kf2":
                ops.append((OP_KF2_PREDICT, dict(A=A, B=B, R=R, c=c, u=u)))
            else:
                ops.append((OP_KF_PREDICT, dict(A=A, B=B, R=R,
                                                c=c if has_c else None, u=u)))
        elif family == "ekf3":
            u = np.array([rng.uniform(0, 1), rng.uniform(-0.5, 0.5)])
            ops.append((OP_EKF3_PREDICT, dict(R=R * 0.1, u=u)))
        else:
            u = rng.normal(size=n) * 0.1
            ops.append((OP_EKF_PREDICT, dict(R=R * 0.1, u=u)))
            truth = g(truth, u)[0] + rng.multivariate_normal(
                np.zeros(n), R * 0.1)
        if rng.random() < 0.2:
            continue  # no measurement this step
        gate = _gate(rng)
        outlier = 30.0 if rng.random() < 0.15 else 0.0
        if family in ("kf2", "kf"):
            m = int(rng.integers(1, (2 if family == "kf2" else n) + 1))
            C = rng.normal(size=(m, n))
            Q = _psd(rng, m, scale=0.3) + np.eye(m) * 0.01
            c = rng.normal(size=m) * 0.1
            has_c = family == "kf2" or bool(rng.random() < 0.5)
            z = rng.normal(size=m) * 2 + outlier
            if family == "kf2":
                ops.append((OP_KF2_UPDATE, dict(m=m, C=C, Q=Q, c=c, gate=gate,
                                                z=z)))
            else:
                ops.append((OP_KF_UPDATE, dict(m=m, C=C, Q=Q,
                                               c=c if has_c else None,
                                               gate=gate, z=z)))
        elif family == "ekf3":
            m = int(rng.integers(1, 3))
            Q = _psd(rng, m, scale=0.2) + np.eye(m) * 0.01
            z = rng.normal(size=m) + outlier
            ops.append((OP_EKF3_UPDATE, dict(m=m, angle_mask=0, Q=Q,
                                             gate=gate, z=z)))
        else:
            m = int(rng.integers(1, n + 1))
            Q = _psd(rng, m, scale=0.2) + np.eye(m) * 0.01
            Qc = np.linalg.cholesky(Q)
            z = (bilinear(np.dtype(np.float64), m)(truth)[0]
                 + Qc @ rng.normal(size=m) + (outlier if gate else 0.0))
            ops.append((OP_EKF_UPDATE, dict(m=m, Q=Q, gate=gate, z=z)))
    return ops


def generate_all(seed, steps=30):
    """Every family of FAMILIES, one after the other, in one scenario."""
    ops = []
    for family, n in FAMILIES:
        ops += generate(family, n, seed, steps)
    return ops


# ---- the file for replay.c ---------------------------------------------------

def encode(ops, dtype):
    dt = np.dtype(dtype).newbyteorder("<")
    out = [b"GFRP", struct.pack("<I", dt.itemsize)]

    def u32(v):
        out.append(struct.pack("<I", int(v)))

    def reals(*arrays):
        for a in arrays:
            out.append(np.asarray(a, dtype=dt).tobytes())

    for code, f in ops:
        u32(code)
        if code == OP_KF2_INIT or code == OP_EKF3_INIT:
            reals(f["mu"], f["sigma"])
        elif code == OP_KF2_PREDICT:
            reals(f["A"], f["B"], f["R"], f["c"])
            u32(f["u"] is not None)
            reals(f["u"] if f["u"] is not None else np.zeros(2))
        elif code == OP_KF2_UPDATE:
            u32(f["m"])
            reals(f["C"], f["Q"], f["c"], [f["gate"]], f["z"])
        elif code == OP_KF_INIT:
            u32(f["n"])
            reals(f["mu"], f["sigma"])
        elif code == OP_KF_PREDICT:
            u32(f["B"].shape[1])
            u32(f["c"] is not None)
            reals(f["A"], f["B"], f["R"])
            if f["c"] is not None:
                reals(f["c"])
            u32(f["u"] is not None)
            if f["u"] is not None:
                reals(f["u"])
        elif code == OP_KF_UPDATE:
            u32(f["m"])
            u32(f["c"] is not None)
            reals(f["C"], f["Q"])
            if f["c"] is not None:
                reals(f["c"])
            reals([f["gate"]], f["z"])
        elif code == OP_EKF3_PREDICT:
            reals(f["R"], f["u"])
        elif code == OP_EKF3_UPDATE:
            u32(f["m"])
            u32(f["angle_mask"])
            reals(f["Q"], [f["gate"]], f["z"])
        elif code == OP_EKF_INIT:
            u32(f["n"])
            u32(f["angles"])
            reals(f["mu"], f["sigma"])
        elif code == OP_EKF_PREDICT:
            reals(f["R"], f["u"])
        elif code == OP_EKF_UPDATE:
            u32(f["m"])
            reals(f["Q"], [f["gate"]], f["z"])
    u32(OP_END)
    return b"".join(out)


# ---- the same through the package ----------------------------------------------

def run_python(ops, mod):
    """The records of replay.c, computed by the package module `mod`
    (gaussfilt.float32 or gaussfilt.float64)."""
    dt = mod.dtype
    out = []
    filt = None
    g_cubic = cubic(dt)

    def record(status, info=None):
        out.append(struct.pack("<iI", status, filt.mu.shape[0]))
        out.append(np.asarray(filt.mu, dt).tobytes())
        out.append(np.asarray(filt.sigma, dt).tobytes())
        if info is not None and status in (0, gaussfilt.Gated.status):
            nis, y = info
            out.append(np.asarray([nis], dt).tobytes())
            out.append(np.asarray(y, dt).tobytes())

    def step(fn):
        """Runs fn; the status and, for an update, (nis, innovation)."""
        try:
            fn()
            return 0, (filt.nis, filt.innovation)
        except gaussfilt.Gated as e:
            return e.status, (e.nis, e.innovation)
        except gaussfilt.GaussfiltError as e:
            return e.status, None

    for code, f in ops:
        if code in (OP_KF2_INIT, OP_KF_INIT, OP_EKF3_INIT, OP_EKF_INIT):
            cls = {OP_KF2_INIT: mod.KF2, OP_KF_INIT: mod.KF,
                   OP_EKF3_INIT: mod.EKF3, OP_EKF_INIT: mod.EKF}[code]
            args = (f["mu"], f["sigma"]) + ((f["angles"],)
                                            if code == OP_EKF_INIT else ())
            try:
                filt = cls(*args)
                st = 0
            except gaussfilt.GaussfiltError as e:
                st = e.status
            record(st)
            continue
        if code == OP_KF2_PREDICT:
            st, _ = step(lambda: filt.predict(
                mod.KF2Model(f["A"], f["R"], f["B"], f["c"]), f["u"]))
        elif code == OP_KF_PREDICT:
            nu = f["B"].shape[1]
            st, _ = step(lambda: filt.predict(
                mod.KFModel(f["A"], f["R"], f["B"] if nu else None, f["c"]),
                f["u"]))
        elif code == OP_EKF3_PREDICT:
            st, _ = step(lambda: filt.predict(
                mod.EKF3Motion(mod.forward_turn, f["R"]), f["u"]))
        elif code == OP_EKF_PREDICT:
            st, _ = step(lambda: filt.predict(
                mod.EKFMotion(g_cubic, f["R"]), f["u"]))
        elif code == OP_KF2_UPDATE:
            st, info = step(lambda: filt.update(
                mod.KF2Meas(f["C"], f["Q"], f["c"], f["gate"]), f["z"]))
        elif code == OP_KF_UPDATE:
            st, info = step(lambda: filt.update(
                mod.KFMeas(f["C"], f["Q"], f["c"], f["gate"]), f["z"]))
        elif code == OP_EKF3_UPDATE:
            h = mod.meas_x if f["m"] == 1 else mod.meas_xy
            st, info = step(lambda: filt.update(
                mod.EKF3Meas(h, f["Q"], f["angle_mask"], f["gate"]), f["z"]))
        elif code == OP_EKF_UPDATE:
            st, info = step(lambda: filt.update(
                mod.EKFMeas(bilinear(dt, f["m"]), f["Q"], filt.n, 0,
                            f["gate"]), f["z"]))
        else:
            raise ValueError("unknown operation %d" % code)
        record(st, info if code in UPDATES else None)
    return b"".join(out)


def split_records(ops, data, dtype):
    """The records of `data` (replay.c's output), one per operation, as
    bytes: to name the first operation where two runs differ."""
    size = np.dtype(dtype).itemsize
    recs, pos = [], 0
    for code, f in ops:
        st, n = struct.unpack_from("<iI", data, pos)
        end = pos + 8 + size * (n + n * n)
        if code in UPDATES and st in (0, gaussfilt.Gated.status):
            end += size * (1 + f["m"])
        recs.append(data[pos:end])
        pos = end
    return recs, pos
