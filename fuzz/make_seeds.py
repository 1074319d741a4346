#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes the seed corpus of fuzz_core (fuzz/corpus/core/), in the input
encoding described at the top of fuzz_core.c: the book's exercises as call
programs, plus one input per helper. Run once; the output is committed."""
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "core")
SPECIAL = {0.01: 203, 1e4: 206, -0.7: 226, 0.68: 227, 1e30: 212}


def real(v):
    """One real: on the 0.25 grid when it is, else a special, else raw."""
    if v in SPECIAL:
        return bytes([SPECIAL[v]])
    g = v * 4
    if g == int(g) and -100 <= g < 100:
        return bytes([int(g) + 100])
    return bytes([240]) + struct.pack("<d", v)


def reals(*vs):
    return b"".join(real(v) for v in vs)


def cov(*vs):
    return b"\x00" + reals(*vs)  # flag 0: symmetric


KF2_PREDICT = (bytes([1]) + reals(1, 1, 0, 1) + reals(0, 0, 0, 0) +
               cov(0.25, 0.5, 0.5, 1) + reals(0, 0) + reals(0, 0) + b"\x00")


def kf2_update(z, q=10.0, gate=None):
    g = b"\x00" if gate is None else b"\x01" + real(gate)
    return (bytes([2, 1]) + reals(1, 0, 0, 0) + cov(q, 0, 0, 0) +
            reals(0, 0) + g + reals(z, 0))


EKF3_PREDICT = bytes([4, 0]) + reals(1, 0) + cov(*[0] * 9)
EKF3_UPDATE_X = (bytes([5, 0, 1]) + cov(0.01, *[0] * 8) + b"\x00" +
                 reals(-0.7, 0, 0))

seeds = {
    # Exercise 2: four predictions, z = 5 at t = 5 (Table 2.1).
    "exercise2": KF2_PREDICT * 5 + kf2_update(5),
    # The same with a gate the measurement fails.
    "exercise2_gated": KF2_PREDICT * 5 + kf2_update(5, gate=0.25),
    # Exercise 4: move 1 forward, observe x = -0.7 (Table 4.2).
    "exercise4": EKF3_PREDICT + EKF3_UPDATE_X,
    # Exercise 4 again from an explicit init, then (x, y) measured.
    "exercise4_xy": (bytes([3]) + reals(0, 0, 0) +
                     cov(0.01, 0, 0, 0, 0.01, 0, 0, 0, 1e4) + EKF3_PREDICT +
                     bytes([5, 1, 2]) + cov(0.01, 0, 0, 0, 0.01, 0, 0, 0, 0) +
                     b"\x00" + reals(-0.7, 0.7, 0)),
    # A caller-supplied motion model returning a NaN Jacobian.
    "ekf3_callback_nan": (bytes([4, 1]) + reals(1, 0) + cov(*[0] * 9) +
                          b"\x00" + reals(1, 2, 3) + reals(1, 0, 0, 0, 1, 0) +
                          bytes([240]) + struct.pack("<d", float("nan")) +
                          reals(0, 1)),
    # Helpers: correlation, ellipse (p = 0.68), inverse, eigen, Cholesky,
    # angle wrap; then every NULL case.
    "helpers": (bytes([6]) + cov(41.25, 12.5, 12.5, 5) +
                bytes([14]) + cov(41.25, 12.5, 12.5, 5) + real(0.68) +
                bytes([22]) + cov(4, 1, 1, 3) +
                bytes([30]) + cov(2, 1, 1, 0) +
                bytes([38]) + cov(4, 2, 0, 2, 5, 1, 0, 1, 3) + b"\x03" +
                reals(1, 2, 3) + b"\x00\x02" +
                bytes([46]) + real(24)),
    "nulls": b"".join(bytes([7, i]) for i in range(10)),
}

os.makedirs(OUT, exist_ok=True)
for name, data in seeds.items():
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)
print(f"{len(seeds)} seeds in {OUT}")
