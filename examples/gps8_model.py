#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""examples/gps8.c's model written once, for gaussfilt.codegen: 8 states
(position and velocity in an Earth-centred frame, m and m/s; the
receiver's clock bias b and drift d, both times the speed of light, m and
m/s), the motion of white acceleration and a two-state clock, and four
pseudoranges rho_k = |s_k - p| + b, the satellites s_k the parameters
(twelve, s0x s0y s0z s1x ..., as gps8.c's fix holds them).

    python examples/gps8_model.py OUTDIR   # OUTDIR/gps8_model.h, .c

examples/gps8.c runs on either model: its own callbacks, or the
generated gps8_g and gps8_h_rho (built with -DGPS8_GENERATED and the
generated source); python/tests/test_codegen.py runs both and compares
their beliefs and their instruction counts on the Cortex-M4F.
"""
import sys

import sympy as sp  # type: ignore[import-untyped]

from gaussfilt import codegen as cg

NSAT = 4
SIGMA_RHO = 6          # m: pseudorange noise
QACC = sp.Rational(1, 10)  # m^2/s^3: the receiver's acceleration
QB = sp.Rational(1, 10)    # m^2/s: clock bias (white frequency noise)
QD = sp.Rational(1, 100)   # m^2/s^3: clock drift (random-walk frequency)


def model() -> cg.Model:
    x, y, z, vx, vy, vz, b, d = sp.symbols("x y z vx vy vz b d")
    sats = [sp.symbols("s%dx s%dy s%dz" % (k, k, k)) for k in range(NSAT)]
    dt = cg.dt
    R = sp.zeros(8, 8)
    for i in range(3):
        R[i, i] = QACC * dt ** 3 / 3
        R[i, i + 3] = R[i + 3, i] = QACC * dt ** 2 / 2
        R[i + 3, i + 3] = QACC * dt
    R[6, 6] = QB * dt + QD * dt ** 3 / 3
    R[6, 7] = R[7, 6] = QD * dt ** 2 / 2
    R[7, 7] = QD * dt
    rho = [sp.sqrt((sx - x) ** 2 + (sy - y) ** 2 + (sz - z) ** 2) + b
           for sx, sy, sz in sats]
    return cg.Model(
        "gps8",
        states=[cg.State(x, "m"), cg.State(y, "m"), cg.State(z, "m"),
                cg.State(vx, "m/s"), cg.State(vy, "m/s"),
                cg.State(vz, "m/s"), cg.State(b, "m"), cg.State(d, "m/s")],
        params=[s for sat in sats for s in sat],
        motion=[x + vx * dt, y + vy * dt, z + vz * dt, vx, vy, vz,
                b + d * dt, d],
        R=R,
        sensors=[cg.Sensor("rho", rho, Q=sp.eye(NSAT) * SIGMA_RHO ** 2,
                           names=["rho%d" % k for k in range(NSAT)])],
        source="examples/gps8_model.py")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: gps8_model.py OUTDIR")
    for path in cg.write(model(), sys.argv[1]):
        print(path)
