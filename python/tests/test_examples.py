# SPDX-License-Identifier: MIT
"""The Python examples run: examples/notebook.py headless (the book's
tables beside FilterPy, float32 beside float64 on the GPS example), and
the example of docs/python.md (and README.md's, once it has one) as
written."""
import re
import subprocess
import sys

from conftest import ROOT


def test_notebook_runs_and_its_checks_pass(tmp_path):
    r = subprocess.run([sys.executable, ROOT / "examples/notebook.py"],
                       capture_output=True, text=True, timeout=300,
                       cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    out = r.stdout
    assert out.rstrip().endswith("notebook: checks passed")
    assert "FAILED" not in out
    # Table 2.1, Figure 1.2 and Table 4.2 as printed
    assert re.search(r"float32  mu =    4\.0244    1\.2195  Sigma =    8\.0488"
                     r"    2\.4390    1\.9512", out)
    assert re.search(r"FilterPy  1\.000  0\.894  0\.878 .* 0\.867\n", out)
    assert re.search(r"float64  predicted Sigma_yy 10000\.01; corrected mu = "
                     r"   0\.1500", out)
    assert "float32 vs float64: rms" in out


def blocks(path, name):
    text = path.read_text()
    return re.findall(r"<!-- %s -->\n```python\n(.*?)```\n<!-- /%s -->" % (
        name, name), text, re.S)


def test_the_documented_example_runs(tmp_path):
    found = blocks(ROOT / "docs/python.md", "example-python")
    found += blocks(ROOT / "README.md", "example-python")
    assert found, "docs/python.md has no <!-- example-python --> block"
    for code in found:
        assert len(code.strip().splitlines()) <= 12
        r = subprocess.run([sys.executable, "-c", code], capture_output=True,
                           text=True, timeout=60, cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        assert "mu = [4.0244 1.2195]" in r.stdout, r.stdout


def test_every_python_block_of_the_docs_runs(tmp_path):
    """Each ```python block of README.md and docs/ runs as written; what a
    print's comment says it prints (`print(x)  # text`), it prints."""
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    ran = 0
    for page in pages:
        for code in re.findall(r"^```python\n(.*?)^```$", page.read_text(),
                               re.S | re.M):
            r = subprocess.run([sys.executable, "-c", code],
                               capture_output=True, text=True, timeout=120,
                               cwd=tmp_path)
            assert r.returncode == 0, "%s:\n%s%s" % (page.name, code,
                                                     r.stderr)
            for said in re.findall(r"^print\(.*\)\s+#\s*(.+)$", code, re.M):
                assert said.strip() in r.stdout, (page.name, said, r.stdout)
            ran += 1
    assert ran >= 4
