// SPDX-License-Identifier: MIT
// The README's example: exercises 1 and 2 of Probabilistic Robotics
// chapter 3. Five predictions from a known start, then the position
// reading z = 5 with variance 10 (Table 2.1, docs/exercises.md).
#include <stdio.h>

#include "gaussfilt/kf2.h"

int main(void)
{
    static const gf_kf2_model car = {
        .A = {{{1, 1}, {0, 1}}},        // x += v; v unchanged
        .B = {{{0, 0}, {0, 0}}},        // no control
        .R = {{{0.25, 0.5}, {0.5, 1}}}, // random acceleration, variance 1
    };
    static const gf_kf2_meas gps = {
        .m = 1,
        .C = {{{1, 0}}}, // position only
        .Q = {{{10}}},   // variance 10
    };
    const gf_vec2 mu0 = {{0, 0}};
    const gf_mat2 sigma0 = {{{0, 0}, {0, 0}}};
    const gf_vec2 z = {{5}};

    gf_kf2 kf;
    gf_status st = gf_kf2_init(&kf, &mu0, &sigma0);
    for (int t = 1; t <= 5 && st == GF_OK; t++) {
        st = gf_kf2_predict(&kf, &car, NULL);
    }
    gf_innovation info;
    if (st == GF_OK) {
        st = gf_kf2_update(&kf, &gps, &z, &info);
    }
    gf_mat2 sigma; // the belief carries Sigma as factors: read it back
    if (st == GF_OK) {
        st = gf_kf2_cov(&kf, &sigma);
    }
    if (st != GF_OK) {
        fprintf(stderr, "kf2: %s\n", gf_status_str(st));
        return 1;
    }
    printf("mu = (%.4f, %.4f)\n", (double)kf.mu.v[0], (double)kf.mu.v[1]);
    printf("Sigma = ((%.4f, %.4f), (%.4f, %.4f))\n", (double)sigma.m[0][0],
           (double)sigma.m[0][1], (double)sigma.m[1][0], (double)sigma.m[1][1]);
    printf("innovation %.4f, NIS %.4f\n", (double)info.y[0], (double)info.nis);
    return 0;
}
