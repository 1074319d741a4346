# SPDX-License-Identifier: MIT
# LCM for scripts/test.d/20-lcm.sh and scripts/demo: installs what the
# streaming side needs and builds sim/. Sourced after lib.sh, not run.
#
# LCM comes from PyPI (lcm 1.5.x) into the project .venv: lcm-gen, liblcm,
# its CMake config, the Python module, lcm-logger, lcm-logplayer, lcm-spy.
# The wheel links the system's GLib (Debian libglib2.0-0); the multi-process
# tests need ip (iproute2) and unshare (util-linux).

GF_LCM_SPEC='lcm>=1.5,<1.6'

# gf_lcm_setup [PIP_SPEC...]: installs LCM (and any extra Python packages)
# and sets GF_LCM_CMAKE_DIR and GF_LCM_BIN.
gf_lcm_setup() {
    gf_apt cmake make gcc libc6-dev libcmocka-dev libglib2.0-0 iproute2 \
        util-linux
    gf_venv "$GF_LCM_SPEC" "$@"
    GF_LCM_CMAKE_DIR=$("$GF_VENV/bin/python" -c '
import os, lcm
print(os.path.normpath(os.path.join(os.path.dirname(lcm.__file__),
                                    "..", "lib", "lcm", "cmake")))') ||
        gf_die "the lcm Python package in $GF_VENV does not import"
    [ -f "$GF_LCM_CMAKE_DIR/lcmConfig.cmake" ] ||
        gf_die "no lcmConfig.cmake in $GF_LCM_CMAKE_DIR (lcm wheel layout changed?)"
    # The real programs (the .venv/bin ones are Python wrappers that do not
    # pass signals on: a script's SIGINT would never reach lcm-logger).
    GF_LCM_BIN=$(cd "$GF_LCM_CMAKE_DIR/../../../bin" && pwd)
    [ -x "$GF_LCM_BIN/lcm-logger" ] || gf_die "no lcm-logger in $GF_LCM_BIN"
}

# gf_java_gui: the java on PATH can open windows, as lcm-spy needs: its
# JRE has AWT's X11 library, libawt_xawt.so (a headless JRE has not).
gf_java_gui() {
    local java
    java=$(command -v java) || return 1
    java=$(readlink -f "$java")
    [ -e "$(dirname "$java")/../lib/libawt_xawt.so" ] ||
        [ -e "$(dirname "$java")/../jre/lib/amd64/libawt_xawt.so" ]
}

# gf_lcm_build DIR: configures and builds the core + sim/ (double) in DIR,
# then installs the Python types into the venv (gf_lcm_py_install).
gf_lcm_build() {
    local dir=$1
    cmake -S "$GF_ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DGAUSSFILT_BUILD_SIM=ON -Dlcm_DIR="$GF_LCM_CMAKE_DIR" >/dev/null ||
        gf_die "cmake configure of sim/ failed"
    cmake --build "$dir" --parallel 2 >/dev/null ||
        cmake --build "$dir" --parallel 1 ||
        gf_die "build of sim/ failed"
    gf_lcm_py_install "$dir"
}

# gf_lcm_py_install DIR: pip-installs the types lcm-gen made in DIR (the
# package gaussfilt_lcm, sim/CMakeLists.txt writes its pyproject.toml) into
# the venv, when they changed: `import gaussfilt_lcm` then works in
# $GF_VENV/bin/python with no PYTHONPATH (examples/beliefs.py).
gf_lcm_py_install() {
    local src=$1/sim/lcmtypes stamp
    [ -f "$src/pyproject.toml" ] || gf_die "no $src/pyproject.toml (build sim/ first)"
    stamp=$(cat "$src/pyproject.toml" "$src"/gaussfilt_lcm/*.py | sha1sum | cut -c1-40)
    [ "$(cat "$GF_VENV/.gaussfilt_lcm" 2>/dev/null)" = "$stamp" ] &&
        "$GF_VENV/bin/python" -c 'import gaussfilt_lcm' 2>/dev/null && return 0
    gf_venv 'wheel>=0.38' # setuptools builds the package into a wheel
    "$GF_VENV/bin/python" -m pip install -q --disable-pip-version-check \
        --no-deps --no-build-isolation --no-index "$src" >/dev/null 2>&1 ||
        gf_die "pip could not install the Python types from $src"
    rm -rf "$src/build" "$src"/*.egg-info
    echo "$stamp" >"$GF_VENV/.gaussfilt_lcm"
}
