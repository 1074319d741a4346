// SPDX-License-Identifier: MIT
// gps8's model written by hand (gps8.h); examples/gps8_model.py is the
// same model for gaussfilt.codegen.
#include "gps8.h"

gf_status gps8_g(void *ctx, unsigned n, const gf_real *mu, const gf_real *u,
                 gf_real *mu_bar, gf_real *G)
{
    (void)ctx;
    const gf_real dt = u[0];
    for (unsigned i = 0; i < 3u; i++) {
        mu_bar[i] = mu[i] + dt * mu[i + 3u];
        G[i * n + i + 3u] = dt;
    }
    mu_bar[6] = mu[6] + dt * mu[7];
    G[6u * n + 7u] = dt;
    return GF_OK;
}

gf_status gps8_h_rho(void *ctx, unsigned n, unsigned m, const gf_real *mu,
                     gf_real *z, gf_real *H)
{
    const gf_real *s = ctx;
    for (unsigned k = 0; k < m; k++) {
        gf_real d[3], r2 = 0;
        for (unsigned i = 0; i < 3u; i++) {
            d[i] = s[3u * k + i] - mu[i];
            r2 += d[i] * d[i];
        }
        gf_real r = GF_SQRT(r2);
        if (!(r > 0)) {
            return GF_ERR_MODEL;
        }
        z[k] = r + mu[6];
        for (unsigned i = 0; i < 3u; i++) {
            H[k * n + i] = -d[i] / r;
        }
        H[k * n + 6u] = 1;
    }
    return GF_OK;
}
