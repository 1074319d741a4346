# SPDX-License-Identifier: MIT
"""Every build of the package computes the same bits, whatever the
platform and compiler: a fixed scenario of KF2, KF (n = 4, a control
input), EKF3 (the built-in models) and EKF (Python models) steps, gated
updates among them, run through each precision; the SHA-256 of every
record (replay.c's layout: status, mean, covariance, NIS, innovation) is
the one written here, and the C library alone (gf_replay, on this host)
gives the same records.

The scenario's numbers are made without libm or BLAS (Python's
random.random, + - * / and loops), so they are the same everywhere; a
wheel whose compiler fused a multiply and an add (MSVC's /fp:fast, gcc's
default on AArch64 without -ffp-contract=off), or that rounds in extended
precision, fails here. cibuildwheel runs this file on every wheel it
builds (python/pyproject.toml), the C comparison excepted.
"""
import hashlib
import random

import numpy as np
import pytest

import gaussfilt
import scenarios as S

# sha256 of the inputs (encoded in float64) and of the records per precision
INPUTS = "15b2abaef31c7cdad6ebd03546b9ffe4efe65587c7675ad1c6ad0487140684a2"
RECORDS = {
    "float32": "5666e472f2610ed66bb858792e3df3ab5dd613eedadaccd9b6f1fb65b24aa249",
    "float64": "1271f61602822804b047d278d2ef38ffb4ca493b816039b3b0cce3186782903f",
}
MODS = {"float32": gaussfilt.float32, "float64": gaussfilt.float64}
FAMILIES = [("kf2", 2), ("kf", 4), ("ekf3", 3), ("ekf", 3)]
STEPS = 40


def _uniform(r, shape, scale=1.0):
    """Numbers in [-scale, scale): multiples of 2^-20, exact in float32."""
    size = int(np.prod(shape)) if shape else 1
    vals = [scale * (r.randrange(-(1 << 20), 1 << 20) / float(1 << 20))
            for _ in range(size)]
    return np.array(vals, dtype=np.float64).reshape(shape)


def _dot(a, b):
    """a . b added left to right, one rounding per term (Python's sum()
    compensates its rounding from 3.12 on, which gives other bits)."""
    s = 0.0
    for x, y in zip(a, b):
        s = s + x * y
    return s


def _psd(r, n, rank, scale):
    """L L^T, L (n, rank), summed in a fixed order."""
    L = _uniform(r, (n, rank), scale).tolist()
    return np.array([[_dot(L[i], L[j]) for j in range(n)] for i in range(n)])


def portable_ops(seed):
    """The scenario: scenarios.py's operations, numbers from random.Random."""
    r = random.Random(seed)
    ops = []
    for family, n in FAMILIES:
        mu = _uniform(r, (n,))
        sigma = _psd(r, n, n, 0.5)
        if family == "kf2":
            ops.append((S.OP_KF2_INIT, dict(mu=mu, sigma=sigma)))
        elif family == "kf":
            ops.append((S.OP_KF_INIT, dict(n=n, mu=mu, sigma=sigma)))
        elif family == "ekf3":
            ops.append((S.OP_EKF3_INIT, dict(mu=mu, sigma=sigma)))
        else:
            truth = mu * 0.5
            ops.append((S.OP_EKF_INIT, dict(n=n, angles=0, mu=truth,
                                            sigma=sigma * 0.1)))
            g = S.cubic(np.dtype(np.float64))
        for t in range(STEPS):
            R = _psd(r, n, n - 1 if t % 5 == 0 else n, 0.1)
            if family in ("kf2", "kf"):
                A = np.eye(n) + _uniform(r, (n, n), 0.2)
                B = _uniform(r, (n, 2))
                c = _uniform(r, (n,), 0.1)
                u = _uniform(r, (2,)) if t % 3 else None
                code = S.OP_KF2_PREDICT if family == "kf2" else S.OP_KF_PREDICT
                ops.append((code, dict(A=A, B=B, R=R, c=c, u=u)))
            elif family == "ekf3":
                u = np.array([abs(_uniform(r, ())[()]),
                              _uniform(r, (), 0.5)[()]])
                ops.append((S.OP_EKF3_PREDICT, dict(R=R * 0.1, u=u)))
            else:
                u = _uniform(r, (n,), 0.1)
                ops.append((S.OP_EKF_PREDICT, dict(R=R * 0.1, u=u)))
                truth = g(truth, u)[0] + _uniform(r, (n,), 0.05)
            if t % 4 == 3:
                continue  # no measurement this step
            gate = (0.0, 9.0)[t % 2]
            outlier = 30.0 if t % 7 == 5 else 0.0
            m = 1 + t % (2 if family in ("kf2", "ekf3") else n)
            Q = _psd(r, m, m, 0.3) + np.eye(m) * 0.01
            if family in ("kf2", "kf"):
                C = _uniform(r, (m, n))
                c = _uniform(r, (m,), 0.1)
                z = _uniform(r, (m,), 2.0) + outlier
                code = S.OP_KF2_UPDATE if family == "kf2" else S.OP_KF_UPDATE
                ops.append((code, dict(m=m, C=C, Q=Q, c=c, gate=gate, z=z)))
            elif family == "ekf3":
                z = _uniform(r, (m,)) + outlier
                ops.append((S.OP_EKF3_UPDATE, dict(m=m, angle_mask=0, Q=Q,
                                                   gate=gate, z=z)))
            else:
                z = (S.bilinear(np.dtype(np.float64), m)(truth)[0]
                     + _uniform(r, (m,), 0.1) + (outlier if gate else 0.0))
                ops.append((S.OP_EKF_UPDATE, dict(m=m, Q=Q, gate=gate, z=z)))
    return ops


def sha(data):
    return hashlib.sha256(data).hexdigest()


def test_the_inputs_are_the_same_everywhere():
    assert sha(S.encode(portable_ops(1), np.float64)) == INPUTS


@pytest.mark.parametrize("prec", ["float32", "float64"])
def test_the_records_are_the_same_everywhere(prec):
    ops = portable_ops(1)
    out = S.run_python(ops, MODS[prec])
    recs, end = S.split_records(ops, out, MODS[prec].dtype)
    assert end == len(out) and len(recs) == len(ops)
    statuses = {int.from_bytes(r[:4], "little", signed=True) for r in recs}
    assert {0, gaussfilt.Gated.status} <= statuses  # both outcomes of update
    assert sha(out) == RECORDS[prec]


@pytest.mark.parametrize("prec", ["float32", "float64"])
def test_the_records_are_the_c_librarys(replay_bin, tmp_path, prec):
    cprec = {"float32": "float", "float64": "double"}[prec]
    (tmp_path / "in").write_bytes(S.encode(portable_ops(1), MODS[prec].dtype))
    from conftest import run
    run([replay_bin(cprec) / "gf_replay", tmp_path / "in", tmp_path / "out"])
    assert sha((tmp_path / "out").read_bytes()) == RECORDS[prec]
