// SPDX-License-Identifier: MIT
// kf.h and ekf.h from C++17: a 2-D constant-velocity target (x, vx, y, vy)
// with (x, y) measured, one step through gf_kf and one through gf_ekf with
// a callback; both must give the same mean to within rounding. Prints
// "kf_cxx: gf_kf and gf_ekf agree" and returns 0 when they do.
#include <cmath>
#include <cstdio>

#include "gaussfilt/ekf.h"
#include "gaussfilt/kf.h"

namespace
{

const gf_real A[16] = {1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1};
const gf_real R[16] = {GF_R(0.25), GF_R(0.5), 0, 0, GF_R(0.5), 1, 0, 0, 0, 0,
                       GF_R(0.25), GF_R(0.5), 0, 0, GF_R(0.5), 1};
const gf_real C[8] = {1, 0, 0, 0, 0, 0, 1, 0};
const gf_real Q[4] = {4, 1, 1, 4};

extern "C" gf_status motion(void *, unsigned n, const gf_real *mu,
                            const gf_real *, gf_real *mu_bar, gf_real *G)
{
    for (unsigned i = 0; i < n; i++) {
        mu_bar[i] = 0;
        for (unsigned j = 0; j < n; j++) {
            mu_bar[i] += A[i * n + j] * mu[j];
            G[i * n + j] = A[i * n + j];
        }
    }
    return GF_OK;
}

extern "C" gf_status meas(void *, unsigned n, unsigned m, const gf_real *mu_bar,
                          gf_real *z_hat, gf_real *H)
{
    for (unsigned i = 0; i < m; i++) {
        for (unsigned j = 0; j < n; j++) {
            z_hat[i] += C[i * n + j] * mu_bar[j];
            H[i * n + j] = C[i * n + j];
        }
    }
    return GF_OK;
}

gf_kf_work work;
gf_kf kf, ekf;

} // namespace

int main()
{
    const gf_real mu[4] = {0, 1, 0, -1};
    const gf_real sigma[16] = {10, 0, 0,  0, 0, 1, 0, 0,
                               0,  0, 10, 0, 0, 0, 0, 1};
    const gf_real z[2] = {GF_R(1.5), GF_R(-0.5)};
    const gf_kf_model model = {0, A, nullptr, R, nullptr};
    const gf_kf_meas me = {2, C, Q, nullptr, 0};
    const gf_ekf_motion emo = {motion, nullptr, R};
    const gf_ekf_meas eme = {2, meas, nullptr, Q, 0, 0};
    gf_kf_innovation info{};
    if (gf_kf_init(&kf, 4, mu, sigma, &work) != GF_OK ||
        gf_kf_predict(&kf, &model, nullptr, &work) != GF_OK ||
        gf_kf_update(&kf, &me, z, &info, &work) != GF_OK ||
        gf_ekf_init(&ekf, 4, mu, sigma, 0, &work) != GF_OK ||
        gf_ekf_predict(&ekf, &emo, nullptr, &work) != GF_OK ||
        gf_ekf_update(&ekf, &eme, z, nullptr, &work) != GF_OK) {
        std::puts("kf_cxx: a step failed");
        return 1;
    }
    gf_real s[16];
    if (gf_kf_cov(&kf, s) != GF_OK) {
        return 1;
    }
    for (int i = 0; i < 4; i++) {
        const double d = static_cast<double>(kf.mu[i] - ekf.mu[i]);
        if (!(std::fabs(d) <=
              1e-5 * (1.0 + std::fabs(static_cast<double>(kf.mu[i]))))) {
            std::printf("kf_cxx: mu[%d] %g against %g\n", i,
                        static_cast<double>(kf.mu[i]),
                        static_cast<double>(ekf.mu[i]));
            return 1;
        }
    }
    std::printf("kf_cxx: gf_kf and gf_ekf agree: mu = (%.4f, %.4f, %.4f, "
                "%.4f), NIS %.4f, Sigma_xx %.4f\n",
                static_cast<double>(kf.mu[0]), static_cast<double>(kf.mu[1]),
                static_cast<double>(kf.mu[2]), static_cast<double>(kf.mu[3]),
                static_cast<double>(info.nis), static_cast<double>(s[0]));
    return 0;
}
