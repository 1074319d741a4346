# SPDX-License-Identifier: MIT
"""The package answers bit for bit what the C library answers: the same
seeded scenarios (scenarios.py: KF2, EKF3 and the any-size KF and EKF at
n = 2, 3, 4 and 8, gated updates among them) through

- the package (x86-64, the library at -O3, in the package's build),
- gf_replay on the host (the library at -O2, add_subdirectory), and
- gf_fw_replay on QEMU's Cortex-M4F (float, -Os, hard-float FPU),

every belief, NIS and innovation compared as bytes. The conditions it
rests on are checked too: no fused multiply-add in the code (the library
is compiled with -ffp-contract=off; docs/python.md).
"""
import re
import shutil
import struct
import subprocess

import numpy as np
import pytest

import gaussfilt
import scenarios as S
from conftest import BUILD, ROOT, run

SEEDS = [1, 2, 3]
MODS = {"float": gaussfilt.float32, "double": gaussfilt.float64}


def first_difference(ops, a, b, dtype):
    ra, _ = S.split_records(ops, a, dtype)
    rb, _ = S.split_records(ops, b, dtype)
    for i, (x, y) in enumerate(zip(ra, rb)):
        if x != y:
            fa = np.frombuffer(x[8:], dtype=dtype)
            fb = np.frombuffer(y[8:], dtype=dtype)
            return ("operation %d (code %d): statuses %d / %d, first values "
                    "%s / %s" % (i, ops[i][0], struct.unpack_from("<i", x)[0],
                                 struct.unpack_from("<i", y)[0], fa[:4], fb[:4]))
    return "lengths %d / %d" % (len(a), len(b))


def check_same(ops, c_out, mod):
    py_out = S.run_python(ops, mod)
    assert c_out == py_out, first_difference(ops, c_out, py_out, mod.dtype)
    recs, end = S.split_records(ops, py_out, mod.dtype)
    assert end == len(py_out) and len(recs) == len(ops)
    # the scenarios exercise both outcomes of an update
    statuses = {struct.unpack_from("<i", r)[0] for r in recs}
    assert 0 in statuses and gaussfilt.Gated.status in statuses


@pytest.mark.parametrize("prec", ["double", "float"])
@pytest.mark.parametrize("seed", SEEDS)
def test_host_driver(replay_bin, tmp_path, prec, seed):
    mod = MODS[prec]
    ops = S.generate_all(seed)
    (tmp_path / "in").write_bytes(S.encode(ops, mod.dtype))
    run([replay_bin(prec) / "gf_replay", tmp_path / "in", tmp_path / "out"])
    check_same(ops, (tmp_path / "out").read_bytes(), mod)


@pytest.mark.parametrize("seed", SEEDS)
def test_qemu_cortex_m4f(firmware_replay, tmp_path, seed):
    ops = S.generate_all(seed)
    (tmp_path / "replay.in").write_bytes(S.encode(ops, np.float32))
    r = run(["qemu-system-arm", "-M", "mps2-an386", "-nographic",
             "-monitor", "none", "-serial", "none",
             "-semihosting-config", "enable=on,target=native",
             "-kernel", firmware_replay / "gf_fw_replay.elf"],
            cwd=tmp_path, timeout=300)
    assert "operations" in r.stdout
    check_same(ops, (tmp_path / "replay.out").read_bytes(), gaussfilt.float32)


def test_scenarios_cover_the_sizes():
    ops = S.generate_all(1)
    sizes = {f["n"] for code, f in ops if code in (S.OP_KF_INIT, S.OP_EKF_INIT)}
    assert sizes == {2, 3, 4, 8}
    codes = {code for code, _ in ops}
    assert {S.OP_KF2_UPDATE, S.OP_EKF3_UPDATE, S.OP_KF_UPDATE,
            S.OP_EKF_UPDATE} <= codes


# ---- the conditions: no contraction into FMA -------------------------------

def test_library_compiled_without_contraction(replay_bin):
    """The library's own compile flags say -ffp-contract=off (gcc's
    default under -std=c99 too; clang contracts by default)."""
    flags = (replay_bin("float") / "gaussfilt/CMakeFiles/gaussfilt.dir/flags.make")
    assert re.search(r"^C_FLAGS = .*-ffp-contract=off", flags.read_text(), re.M)


def test_host_code_has_no_fma():
    """x86-64: no FMA3 instruction in the package's modules (none is in
    the baseline ISA; -march=native with -ffp-contract=fast would add
    them)."""
    objdump = shutil.which("objdump")
    assert objdump, "objdump (binutils) is needed"
    for mod in (gaussfilt._f32, gaussfilt._f64):
        asm = subprocess.run([objdump, "-d", mod.__file__], capture_output=True,
                             text=True, check=True).stdout
        assert "kf2_update_prepared" in asm
        assert not re.search(r"\bvfn?m(add|sub)\d+[sp][sd]\b", asm), mod.__file__


def test_target_has_fma_and_the_library_uses_none(firmware_replay, tmp_path):
    """Cortex-M4F has a fused VFMA.F32: gcc emits it for a * b + c when
    contraction is allowed (so the check below can fail), and the
    library's code has none (VMLA, which it may use, rounds the product
    first: the same result as a multiply and an add)."""
    src = tmp_path / "fma.c"
    src.write_text("float f(float a, float b, float c) { return a * b + c; }\n")
    flags = ["-mcpu=cortex-m4", "-mthumb", "-mfloat-abi=hard",
             "-mfpu=fpv4-sp-d16", "-O2", "-c"]
    for contract, expect in (("fast", True), ("off", False)):
        obj = tmp_path / ("fma-%s.o" % contract)
        run(["arm-none-eabi-gcc", *flags, "-ffp-contract=" + contract, src,
             "-o", obj])
        asm = run(["arm-none-eabi-objdump", "-d", obj]).stdout
        assert bool(re.search(r"\bvfn?m[as]\.f32\b", asm)) == expect, asm
    lib = firmware_replay / "gaussfilt" / "libgaussfilt.a"
    asm = run(["arm-none-eabi-objdump", "-d", lib]).stdout
    assert "gf_kf2_update" in asm
    assert not re.search(r"\bvfn?m[as]\.f32\b", asm)
