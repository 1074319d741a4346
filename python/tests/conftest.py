# SPDX-License-Identifier: MIT
"""Shared fixtures: the checkout, the build folder, and the C programs the
bit-identity tests compare the package with (built here with CMake).

GF_BUILD (default: the checkout's build/) says where to build. With
GF_PY_REQUIRE_FIRMWARE=1 (scripts/test python sets it after installing the
Arm toolchain and QEMU) a missing tool fails the QEMU test instead of
skipping it; with GF_PY_REQUIRE_PYTHONS=1 (scripts/test python sets it) a
missing CPython minor fails the tests of the stable-ABI wheel on it.
"""
import glob
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("GF_BUILD", ROOT / "build"))
sys.path.insert(0, str(pathlib.Path(__file__).parent))


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise RuntimeError("%s failed (%d):\n%s%s" % (
            " ".join(map(str, cmd)), r.returncode, r.stdout, r.stderr))
    return r


@pytest.fixture(scope="session")
def replay_bin():
    """gf_replay for the host, per precision ("float" or "double"): the
    library at -O2, as a project takes it by add_subdirectory()."""
    made = {}

    def get(prec):
        if prec not in made:
            d = BUILD / "py" / ("replay-" + prec)
            run(["cmake", "-S", ROOT / "python/tests/replay", "-B", d,
                 "-DCMAKE_BUILD_TYPE=RelWithDebInfo",
                 "-DGAUSSFILT_SINGLE_PRECISION=" +
                 ("ON" if prec == "float" else "OFF")])
            run(["cmake", "--build", d, "--parallel", "2"])
            made[prec] = d
        return made[prec]
    return get


@pytest.fixture(scope="session")
def firmware_replay():
    """The Cortex-M4F replay image (float, -Os) and the QEMU to run it."""
    need_firmware_tools("arm-none-eabi-gcc", "arm-none-eabi-objdump",
                        "qemu-system-arm")
    r = run(["bash", "-c", '. scripts/lib.sh && . scripts/firmware.sh && '
             'GF_FW_VARIANT=replay gf_fw_build cortex-m4f float '
             '-DGF_FW_REPLAY=ON | tail -1'], cwd=ROOT,
            env=dict(os.environ, GF_BUILD=str(BUILD)))
    return pathlib.Path(r.stdout.strip())


def need_firmware_tools(*need):
    """Skips the test (or, with GF_PY_REQUIRE_FIRMWARE=1, fails it) when
    any of the programs named is missing."""
    missing = [t for t in need if not shutil.which(t)]
    if missing:
        msg = "missing %s (scripts/test python installs them)" % " ".join(
            missing)
        if os.environ.get("GF_PY_REQUIRE_FIRMWARE") == "1":
            pytest.fail(msg)
        pytest.skip(msg)


def need_python(minor):
    """The interpreter of CPython 3.minor: python3.minor on PATH, else
    pyenv's (PYENV_ROOT, default ~/.pyenv: versions/3.minor.*/bin), the
    first that runs and says it is 3.minor. When there is none the test
    is skipped (or, with GF_PY_REQUIRE_PYTHONS=1, fails), saying so."""
    name = "python3.%d" % minor
    root = os.environ.get("PYENV_ROOT", os.path.expanduser("~/.pyenv"))
    found = [shutil.which(name)] + sorted(glob.glob(os.path.join(
        root, "versions", "3.%d.*" % minor, "bin", name)), reverse=True)
    if sys.version_info[:2] == (3, minor):
        found.insert(0, sys.executable)
    for exe in filter(None, found):
        try:
            r = subprocess.run([exe, "-c", "import sys, venv; "
                                "print(*sys.version_info[:2])"],
                               capture_output=True, text=True, timeout=60)
        except OSError:
            continue
        if r.returncode == 0 and r.stdout.split() == ["3", str(minor)]:
            return exe
    msg = ("no CPython 3.%d here (%s on PATH or %s/versions/3.%d.*/bin): the "
           "abi3 wheel is not tested on it" % (minor, name, root, minor))
    if os.environ.get("GF_PY_REQUIRE_PYTHONS") == "1":
        pytest.fail(msg)
    pytest.skip(msg)


def run_export_on_m4f(files, variant):
    """Builds C files written by gaussfilt.export_c (the exported run
    first, then the sources of the models it uses) into the Cortex-M4F
    image gf_fw_export (float, -Os; firmware/CMakeLists.txt) and runs it on
    QEMU's mps2-an386; returns what it printed. Skips (or, with
    GF_PY_REQUIRE_FIRMWARE=1, fails) without the Arm toolchain and QEMU."""
    need_firmware_tools("arm-none-eabi-gcc", "qemu-system-arm")
    r = run(["bash", "-c", '. scripts/lib.sh && . scripts/firmware.sh && '
             'GF_FW_VARIANT="$0" gf_fw_build cortex-m4f float '
             '-DGF_FW_EXPORT="$1" | tail -1', variant,
             ";".join(str(f) for f in files)],
            cwd=ROOT, env=dict(os.environ, GF_BUILD=str(BUILD)))
    elf = os.path.join(r.stdout.strip(), "gf_fw_export.elf")
    q = run(["qemu-system-arm", "-M", "mps2-an386", "-nographic",
             "-monitor", "none", "-serial", "none",
             "-semihosting-config", "enable=on,target=native",
             "-kernel", elf], cwd=os.path.dirname(str(files[0])), timeout=300)
    return q.stdout.strip()
