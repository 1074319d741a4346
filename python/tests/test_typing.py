# SPDX-License-Identifier: MIT
"""Types and signatures: what an editor, a type checker and Jupyter see.

- inspect.signature gives every class, method and function of both
  modules (the C docstrings' text signatures);
- mypy's stubtest finds the stubs (float64.pyi, and float32.pyi made
  from it at build time) and the modules in agreement: every name, every
  parameter and default;
- mypy --strict and pyright (strict) pass on every Python example of
  README.md and docs/, as written there;
- and both do type-check: a wrong model, a float64 model given to a
  float32 filter and a float32 mean taken for a float64 one are each
  reported, and the arrays come out with their dtype.
"""
import inspect
import json
import os
import re
import subprocess
import sys

import pytest

import gaussfilt
from conftest import ROOT

MODS = [gaussfilt.float32, gaussfilt.float64]


def public_callables(mod):
    """(qualified name, object) of every class, method and function."""
    for name in mod.__all__:
        obj = getattr(mod, name)
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
            yield name, obj
            for attr, v in vars(obj).items():
                if not attr.startswith("_") and callable(v):
                    yield name + "." + attr, getattr(obj, attr)
        elif callable(obj):
            yield name, obj


@pytest.mark.parametrize("mod", MODS, ids=lambda m: m.__name__)
def test_every_signature_is_readable(mod):
    seen = {}
    for name, obj in public_callables(mod):
        seen[name] = str(inspect.signature(obj))
    assert seen["KF2"] == "(mu, sigma)"
    assert seen["KF2.predict"] == "(self, /, model, u=None)"
    assert seen["EKF.run"] == ("(self, /, motion=None, meas=None, u=None, "
                               "z=None, steps=None)")
    assert seen["EKFMeas"] == "(h, Q, n, angle_mask=0, gate=0.0)"
    assert seen["ellipse"] == "(sigma, p=0.68)"
    assert seen["forward_turn"] == "(mu, u, /)"
    assert seen["meas_xy"] == "(mu_bar, /)"
    # the docstring's first line is the text after the signature
    assert mod.KF2.update.__doc__.startswith("Correction")


def mypy_ini(tmp_path):
    """A configuration of mypy's defaults (no project's file applies)."""
    f = tmp_path / "mypy.ini"
    f.write_text("[mypy]\n")
    return str(f)


def test_the_stubs_match_the_modules(tmp_path):
    r = subprocess.run([sys.executable, "-m", "mypy.stubtest",
                        "--mypy-config-file", mypy_ini(tmp_path),
                        "gaussfilt.float64", "gaussfilt.float32"],
                       capture_output=True, text=True, cwd=tmp_path,
                       timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    stubs = {m.__name__: m.__file__[:-3] + ".pyi" for m in MODS}
    f32 = open(stubs["gaussfilt.float32"]).read()
    f64 = open(stubs["gaussfilt.float64"]).read()
    assert "float64" not in f32 and f32 == f64.replace("float64", "float32")


def examples():
    """Every ```python block of README.md and docs/*.md, by place."""
    found = {}
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = page.read_text()
        for m in re.finditer(r"^```python\n(.*?)^```$", text, re.S | re.M):
            line = text.count("\n", 0, m.start()) + 2
            found["%s_%d" % (page.stem.lower(), line)] = m.group(1)
    return found


# A use that must not type-check, line by line (the lines marked "error"),
# and what the arrays are (reveal_type).
WRONG = '''\
import numpy as np
from numpy.typing import NDArray
from gaussfilt import float32 as gf32
from gaussfilt import float64 as gf
kf = gf.KF2(mu=[0, 0], sigma=np.eye(2))
kf32 = gf32.KF2(mu=[0, 0], sigma=np.eye(2))
meas = gf.KF2Meas(C=[[1, 0]], Q=[[1]])
kf.predict(meas)  # error: a measurement is no motion model
kf32.predict(gf.KF2Model(A=np.eye(2), R=np.eye(2)))  # error: float64's
mu: NDArray[np.float64] = kf32.mu  # error: a float32 array
reveal_type(kf.mu)
reveal_type(kf32.run(steps=3))
'''


def assert_dtypes(notes):
    """reveal_type's two notes: a float64 mean; a float32 run's mu, sigma
    and nis, and its int8 statuses (as each checker spells numpy's types:
    float64 or floating[_64Bit])."""
    assert len(notes) == 2, notes
    notes = [re.sub(r"\bnumpy\.([\w.]*\.)?", "", n) for n in notes]
    f64 = r"(float64|floating\[_64Bit\])"
    f32 = r"(float32|floating\[_32Bit\])"
    i8 = r"(int8|signedinteger\[_8Bit\])"
    assert re.search(r"ndarray\[.*dtype\[%s\]\]" % f64, notes[0]), notes
    assert len(re.findall(r"dtype\[%s\]" % f32, notes[1])) == 3, notes
    assert re.search(r"dtype\[%s\]\]\]$" % i8, notes[1].rstrip('"')), notes
    assert "Any]" not in notes[1].replace("tuple[Any, ...]", ""), notes


def write_examples(tmp_path):
    found = examples()
    assert any(k.startswith("readme_") for k in found), found.keys()
    assert any(k.startswith("python_") for k in found), found.keys()
    files = []
    for key, code in sorted(found.items()):
        f = tmp_path / ("ex_%s.py" % key)
        f.write_text(code)
        files.append(f)
    return files


def error_lines(text):
    return [i + 1 for i, line in enumerate(text.splitlines())
            if "# error" in line]


def test_mypy_strict_passes_on_the_examples(tmp_path):
    files = write_examples(tmp_path)
    r = subprocess.run([sys.executable, "-m", "mypy", "--strict",
                        "--config-file", mypy_ini(tmp_path),
                        "--cache-dir", str(tmp_path / "cache"),
                        *[f.name for f in files]],
                       capture_output=True, text=True, cwd=tmp_path,
                       timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "Success: no issues found in %d source files" % len(files) \
        in r.stdout


def test_mypy_finds_the_wrong_uses(tmp_path):
    (tmp_path / "wrong.py").write_text(WRONG)
    r = subprocess.run([sys.executable, "-m", "mypy", "--strict",
                        "--config-file", mypy_ini(tmp_path),
                        "--cache-dir", str(tmp_path / "cache"), "wrong.py"],
                       capture_output=True, text=True, cwd=tmp_path,
                       timeout=600)
    out = r.stdout
    errors = sorted({int(m.group(1)) for m in
                     re.finditer(r"^wrong\.py:(\d+): error", out, re.M)})
    assert errors == error_lines(WRONG), out
    notes = re.findall(r"Revealed type is \"(.*)\"", out)
    assert len(notes) == 2, out
    assert_dtypes(notes)


def pyright(tmp_path, files):
    (tmp_path / "pyrightconfig.json").write_text(json.dumps({
        "typeCheckingMode": "strict", "pythonVersion": "%d.%d"
        % sys.version_info[:2]}))
    env = dict(os.environ, PYRIGHT_PYTHON_IGNORE_WARNINGS="1")
    r = subprocess.run([sys.executable, "-m", "pyright", "--outputjson",
                        "--pythonpath", sys.executable,
                        *[str(f.name) for f in files]],
                       capture_output=True, text=True, cwd=tmp_path, env=env,
                       timeout=600)
    try:
        return json.loads(r.stdout)
    except ValueError:
        pytest.fail("pyright did not run: %s%s" % (r.stdout, r.stderr))


def test_pyright_strict_passes_on_the_examples(tmp_path):
    files = write_examples(tmp_path)
    out = pyright(tmp_path, files)
    assert out["summary"]["filesAnalyzed"] == len(files), out["summary"]
    problems = [d for d in out["generalDiagnostics"]
                if d["severity"] in ("error", "warning")]
    assert problems == [], json.dumps(problems, indent=1)


def test_pyright_finds_the_wrong_uses(tmp_path):
    f = tmp_path / "wrong.py"
    f.write_text(WRONG)
    out = pyright(tmp_path, [f])
    diags = out["generalDiagnostics"]
    errors = sorted({d["range"]["start"]["line"] + 1 for d in diags
                     if d["severity"] == "error"})
    assert errors == error_lines(WRONG), json.dumps(diags, indent=1)
    notes = [d["message"] for d in diags if "reveal_type" in d.get("rule", "")
             or d["severity"] == "information"]
    assert_dtypes(notes)
