// SPDX-License-Identifier: MIT
// The model gps8.c runs (8 states: position and velocity in an
// Earth-centred frame, the clock's bias b and drift d; 4 pseudoranges per
// fix): the motion and the pseudoranges as gf_ekf callbacks, with the
// signatures gaussfilt.codegen writes. gps8_hand.c is the model written by
// hand; examples/gps8_model.py writes the same model as generated C
// (gps8_model.c), which links in its place (python/tests/test_codegen.py
// builds gps8 on each and compares their beliefs and their cost on the
// Cortex-M4F).
#ifndef GF_EXAMPLES_GPS8_H
#define GF_EXAMPLES_GPS8_H

#include "gaussfilt/ekf.h"

// mu_bar = F mu: position += velocity dt, bias += drift dt; G = F. u: dt
// (u[0]); ctx unused.
gf_status gps8_g(void *ctx, unsigned n, const gf_real *mu, const gf_real *u,
                 gf_real *mu_bar, gf_real *G);

// rho_k = |s_k - p| + b, H_k = (-(s_k - p) / |s_k - p|, 0, 0, 0, 1, 0), for
// m = 4 satellites; ctx: their positions, 12 gf_real (s_0x, s_0y, s_0z,
// s_1x, ...).
gf_status gps8_h_rho(void *ctx, unsigned n, unsigned m, const gf_real *mu,
                     gf_real *z, gf_real *H);

#endif
