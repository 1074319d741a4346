# SPDX-License-Identifier: MIT
"""Back to C (gaussfilt.export_c): seeded runs of KF2, KF (n = 4, a
control input, m = 1 and 2, gated and singular updates), EKF3, UKF3 and
PF3 (the built-in models; PF3 with resampling, checked through its
generator, a hash of its particles, its estimate and neff) recorded in
Python (EKF with generated models: test_codegen.py), written as C,
compiled against the checkout's include/ and src/ as a firmware project
vendors them, and run: every status, mean, covariance, innovation and NIS
must be the recorded bytes, on the host in both precisions (gcc, and
clang where present) and on QEMU's Cortex-M4F in float (PF3 included:
its exp, log and atan2 are the library's own, not glibc's or newlib's).
A perturbed expected value (a PF3's seed,
generator word or hash; a UKF3's alpha) and a build in the wrong
precision must fail.
"""
import re
import shutil

import numpy as np
import pytest

import gaussfilt
from conftest import ROOT, run, run_export_on_m4f

MODS = {"float": gaussfilt.float32, "double": gaussfilt.float64}
FLAGS = ["-std=c99", "-O2", "-ffp-contract=off", "-Wall", "-Wextra",
         "-Wpedantic", "-Wconversion", "-Wdouble-promotion", "-Werror"]


def _steps(rec, rng, steps, predict, updates):
    """predict each step, then one of `updates` (meas, z) or none; a
    refused update is recorded and the run goes on."""
    for _ in range(steps):
        predict()
        k = rng.integers(len(updates) + 1)
        if k < len(updates):
            meas, z = updates[k]()
            try:
                rec.update(meas, z)
            except (gaussfilt.Gated, gaussfilt.Singular):
                pass


def kf2_run(gf, seed, nu=2):
    rng = np.random.default_rng(seed)
    dt = 0.1 + rng.random()
    G = np.array([[dt * dt / 2], [dt]])
    car = gf.KF2Model(A=[[1, dt], [0, 1]], R=0.3 * G @ G.T,
                      B=rng.normal(size=(2, nu)), c=rng.normal(size=2) * 0.01)
    L = np.tril(rng.normal(size=(2, 2)))
    pos = gf.KF2Meas(C=[[1, 0]], Q=[[rng.random() + 0.1]], gate=6.0)
    both = gf.KF2Meas(C=rng.normal(size=(2, 2)), Q=L @ L.T + 0.01 * np.eye(2),
                      c=rng.normal(size=2))
    rec = gaussfilt.Recorder(gf.KF2, mu=rng.normal(size=2),
                             sigma=np.diag(rng.random(2) + 0.5))
    x = rng.normal(size=2)

    def z_of(meas, spread):
        return (meas.C @ x + (meas.c if meas.c is not None else 0)
                + rng.normal(size=meas.m) * spread)
    _steps(rec, rng, 150, lambda: rec.predict(car, rng.normal(size=nu)),
           [lambda: (pos, z_of(pos, 1 if rng.random() < 0.8 else 30)),
            lambda: (both, z_of(both, 1))])
    return rec


def kf_run(gf, seed):
    rng = np.random.default_rng(seed)
    dt = 0.5
    A = np.kron(np.eye(2), [[1, dt], [0, 1]])
    g = np.array([[dt * dt / 2], [dt]])
    R = np.kron(np.eye(2), g @ g.T)  # rank 2 of 4
    model = gf.KFModel(A=A, R=R, B=rng.normal(size=(4, 2)) * 0.1,
                       c=rng.normal(size=4) * 0.01)
    xy = gf.KFMeas(C=[[1, 0, 0, 0], [0, 0, 1, 0]], Q=[[1, 0.3], [0.3, 2]],
                   gate=9.0)
    v = gf.KFMeas(C=[[0, 1, 0, 0]], Q=[[0.2]], c=[0.5])
    # the same velocity twice without noise: S is singular
    twice = gf.KFMeas(C=[[0, 1, 0, 0], [0, 1, 0, 0]], Q=np.zeros((2, 2)))
    rec = gaussfilt.Recorder(gf.KF, mu=rng.normal(size=4), sigma=np.eye(4))
    _steps(rec, rng, 150, lambda: rec.predict(model, rng.normal(size=2)),
           [lambda: (xy, rng.normal(size=2) * (1 if rng.random() < 0.8
                                               else 40)),
            lambda: (v, rng.normal(size=1)),
            lambda: (twice, [0.1, 0.1])])
    return rec


def ekf3_models(gf):
    motion = gf.EKF3Motion(g=gf.forward_turn,
                           R=np.diag([0.01, 0.01, 0.002]))
    xy = gf.EKF3Meas(h=gf.meas_xy, Q=[[0.05, 0.01], [0.01, 0.05]], gate=9.0)
    x = gf.EKF3Meas(h=gf.meas_x, Q=[[0.02]])
    return motion, xy, x


def turning_steps(gf, rec, rng):
    """The run EKF3 and UKF3 share: 150 turning steps, xy or x measured
    near the mean (one in seven far off)."""
    motion, xy, x = ekf3_models(gf)

    def near(m):
        return rec.mu[:m] + rng.normal(size=m) * (0.2 if rng.random() < 0.85
                                                   else 5)
    _steps(rec, rng, 150,
           lambda: rec.predict(motion, [0.5, rng.uniform(-0.6, 0.6)]),
           [lambda: (xy, near(2)), lambda: (x, near(1))])
    return rec


def ekf3_run(gf, seed):
    rng = np.random.default_rng(seed)
    rec = gaussfilt.Recorder(gf.EKF3, mu=[0, 0, 0.3],
                             sigma=np.diag([0.1, 0.1, 0.05]))
    return turning_steps(gf, rec, rng)


def ukf3_run(gf, seed):
    rng = np.random.default_rng(seed)
    rec = gaussfilt.Recorder(gf.UKF3, mu=[0, 0, 0.3],
                             sigma=np.diag([0.1, 0.1, 0.05]), alpha=0.5,
                             beta=2.0, kappa=1.0)
    return turning_steps(gf, rec, rng)


def pf3_run(gf, seed):
    """64 particles; resampled after about every third update."""
    rng = np.random.default_rng(seed)
    motion, xy, x = ekf3_models(gf)
    rec = gaussfilt.Recorder(gf.PF3, mu=[0, 0, 0.3],
                             sigma=np.diag([0.1, 0.1, 0.05]), n=64,
                             seed=int(rng.integers(2**32)))

    def near(m):
        return rec.mu[:m] + rng.normal(size=m) * (0.2 if rng.random() < 0.85
                                                   else 5)

    def predict():
        if rng.random() < 0.3:
            rec.resample()
        rec.predict(motion, [0.5, rng.uniform(-0.6, 0.6)])
    _steps(rec, rng, 100, predict, [lambda: (xy, near(2)),
                                    lambda: (x, near(1))])
    return rec


RUNS = {"kf2": kf2_run, "kf": kf_run, "ekf3": ekf3_run, "ukf3": ukf3_run,
        "pf3": pf3_run}


def export(tmp_path, kind, prec, seed=1):
    rec = RUNS[kind](MODS[prec], seed)
    path = gaussfilt.export_c(rec, tmp_path / ("%s_%s.c" % (kind, prec)))
    return rec, path


def build_host(path, prec, exe, cc="gcc"):
    flags = FLAGS + ["-I", str(ROOT / "include")]
    if prec == "float":
        flags.append("-DGF_SINGLE_PRECISION")
    srcs = [str(p) for p in sorted((ROOT / "src").glob("*.c"))]
    run([cc] + flags + [str(path)] + srcs + ["-lm", "-o", str(exe)])
    return exe


def statuses(rec):
    return {s["status"] for s in rec.steps}


@pytest.mark.parametrize("prec", ["double", "float"])
@pytest.mark.parametrize("kind", sorted(RUNS))
def test_export_runs_bit_for_bit_on_the_host(tmp_path, kind, prec):
    rec, path = export(tmp_path, kind, prec)
    # the runs take every outcome the C program checks
    assert {0, gaussfilt.Gated.status} <= statuses(rec)
    if kind == "kf":
        assert gaussfilt.Singular.status in statuses(rec)
    exe = build_host(path, prec, tmp_path / kind)
    r = run([str(exe)])
    assert r.stdout.strip() == "%s_%s: %d steps bit for bit" % (
        kind, prec, len(rec.steps))


@pytest.mark.parametrize("prec", ["double", "float"])
def test_export_a_kf2_with_one_control(tmp_path, prec):
    """B (2, 1): the C program's model has B's second column zero and
    each u padded with a zero, as the package gives them to the library."""
    rec = kf2_run(MODS[prec], 4, nu=1)
    assert all(len(s["arg"]) == 1 for s in rec.steps
               if s["op"] == "predict")
    path = gaussfilt.export_c(rec, tmp_path / ("kf2_one_%s.c" % prec))
    r = run([str(build_host(path, prec, tmp_path / "kf2_one"))])
    assert r.stdout.strip() == "kf2_one_%s: %d steps bit for bit" % (
        prec, len(rec.steps))


@pytest.mark.skipif(shutil.which("clang") is None, reason="no clang")
def test_export_runs_bit_for_bit_with_clang(tmp_path):
    rec, path = export(tmp_path, "kf", "float", seed=2)
    r = run([str(build_host(path, "float", tmp_path / "kf", cc="clang"))])
    assert "%d steps bit for bit" % len(rec.steps) in r.stdout


def test_export_finds_a_difference(tmp_path):
    rec, path = export(tmp_path, "kf2", "float")
    text = path.read_text()
    # the last step's mean, one ulp off
    i = len(rec.steps) - 1
    mu = rec.steps[i]["mu"]
    nudged = np.nextafter(mu[0], np.float32(np.inf))
    old = gaussfilt.export._arr(mu, True)
    new = gaussfilt.export._arr([nudged, mu[1]], True)
    assert text.count(old) >= 1
    lines = text.splitlines()
    row = max(k for k, line in enumerate(lines) if old in line)
    lines[row] = lines[row].replace(old, new)
    path.write_text("\n".join(lines) + "\n")
    exe = build_host(path, "float", tmp_path / "nudged")
    r = __import__("subprocess").run([str(exe)], capture_output=True,
                                     text=True)
    assert r.returncode == 1
    step = int(re.search(r"step (\d+) differs", r.stdout).group(1))
    assert step <= i  # the same values may recur; never after the change


@pytest.mark.parametrize("prec", ["double", "float"])
def test_export_of_a_pf3_finds_a_difference(tmp_path, prec):
    """Another seed fails at once; a generator word or a particle hash one
    bit off fails at its step."""
    rec, path = export(tmp_path, "pf3", prec)
    assert {"predict", "update", "resample"} <= {s["op"] for s in rec.steps}
    text = path.read_text()
    i = len(rec.steps) // 2
    s = rec.steps[i]
    init = "%du, %du, &mu0" % (rec.particles, rec.seed)
    word = "0x%08xu" % s["rng"][2]
    digest = "0x%016xull" % s["hash"]
    for old, new, first in (
            (init, "%du, %du, &mu0" % (rec.particles, rec.seed ^ 1), 0),
            (word, "0x%08xu" % (s["rng"][2] ^ 1), i),
            (digest, "0x%016xull" % (s["hash"] ^ 1 << 63), i)):
        assert text.count(old) == 1, old
        path.write_text(text.replace(old, new))
        exe = build_host(path, prec, tmp_path / "nudged")
        r = __import__("subprocess").run([str(exe)], capture_output=True,
                                         text=True)
        assert r.returncode == 1
        if first == 0:
            assert "step 0 differs" in r.stdout, r.stdout
        else:
            assert "step %d differs" % first in r.stdout, r.stdout


def test_export_of_a_ukf3_keeps_its_parameters(tmp_path):
    """alpha, beta and kappa in the C file as recorded: another alpha
    fails at the first step."""
    rec, path = export(tmp_path, "ukf3", "double")
    text = path.read_text()
    line = "static const gf_ukf3_params ukf3_double_params = " \
        "{0x1p-1, 0x1p+1, 0x1p+0};"
    assert line in text
    path.write_text(text.replace(line, line.replace("0x1p-1", "0x1.2p-1")))
    exe = build_host(path, "double", tmp_path / "nudged")
    r = __import__("subprocess").run([str(exe)], capture_output=True,
                                     text=True)
    assert r.returncode == 1 and "step 0 differs" in r.stdout, r.stdout


def test_export_refuses_the_wrong_precision(tmp_path):
    _, path = export(tmp_path, "kf2", "float")
    with pytest.raises(RuntimeError, match="recorded with gaussfilt.float32"):
        build_host(path, "double", tmp_path / "wrong")


def test_export_refuses_python_models(tmp_path):
    gf = gaussfilt.float64
    rec = gaussfilt.Recorder(gf.EKF3, mu=[0, 0, 0], sigma=np.eye(3))

    def g(mu, u):
        return mu, np.eye(3)
    with pytest.raises(gaussfilt.BadArgument, match="forward_turn"):
        rec.predict(gf.EKF3Motion(g=g, R=np.eye(3)), [1, 0])
    with pytest.raises(gaussfilt.BadArgument, match="EKF, UKF3 or PF3"):
        gaussfilt.Recorder(gf.KF2Meas, mu=[0, 0], sigma=np.eye(2))
    for kind, kw in (("UKF3", {}), ("PF3", {"n": 10})):
        other = gaussfilt.Recorder(getattr(gf, kind), mu=[0, 0, 0],
                                   sigma=np.eye(3), **kw)
        with pytest.raises(gaussfilt.BadArgument, match="forward_turn"):
            other.predict(gf.EKF3Motion(g=g, R=np.eye(3)), [1, 0])
        with pytest.raises(gaussfilt.BadArgument, match="meas_x or meas_xy"):
            other.update(gf.EKF3Meas(h=lambda mu: (mu[:1], np.eye(1, 3)),
                                     Q=[[1]]), [0.5])
        assert other.steps == []
    with pytest.raises(gaussfilt.BadArgument, match="needs n"):
        gaussfilt.Recorder(gf.PF3, mu=[0, 0, 0], sigma=np.eye(3))
    with pytest.raises(gaussfilt.BadArgument, match="only a PF3"):
        rec.resample()
    ekf = gaussfilt.Recorder(gf.EKF, mu=[0, 0], sigma=np.eye(2))
    with pytest.raises(gaussfilt.BadArgument, match="gaussfilt.codegen"):
        ekf.predict(gf.EKFMotion(g=lambda mu, u: (mu, np.eye(2)),
                                 R=np.eye(2)))
    assert ekf.steps == []
    with pytest.raises(gaussfilt.BadArgument, match="C identifier"):
        gaussfilt.export_c(rec, tmp_path / "x.c", name="not-an-identifier")
    assert rec.steps == []


def test_export_records_nothing_the_package_refused(tmp_path):
    gf = gaussfilt.float64
    rec = gaussfilt.Recorder(gf.KF2, mu=[0, 0], sigma=np.eye(2))
    meas = gf.KF2Meas(C=[[1, 0]], Q=[[1]])
    with pytest.raises(gaussfilt.BadArgument):
        rec.update(meas, [1, 2, 3])  # a wrong shape: the library not called
    assert rec.steps == []
    rec.update(meas, [1])
    assert len(rec.steps) == 1


def test_export_runs_bit_for_bit_on_the_cortex_m4f(tmp_path):
    """Every filter, PF3 included: its Box-Muller draws, weights and
    estimate call the library's gf_log, gf_exp and gf_atan2, whose bits do
    not depend on the target's libm (newlib's logf, expf and atan2f round
    differently from glibc's)."""
    assert "pf3" in RUNS
    for kind in sorted(RUNS):
        rec, path = export(tmp_path, kind, "float", seed=3)
        assert run_export_on_m4f([path], "export") == \
            "%s_float: %d steps bit for bit" % (kind, len(rec.steps))
