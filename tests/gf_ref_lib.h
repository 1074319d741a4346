// SPDX-License-Identifier: MIT
// Shared by tests/test_random.c and bench/accuracy.c: the filter under test
// (KF2 or EKF3, through the public API) driven by the scenarios of
// tests/gf_ref.h, with the test's own linear EKF3 models. Test code.
#ifndef GF_REF_LIB_H
#define GF_REF_LIB_H

#include "gf_ref.h"

// ---- the test's linear models for EKF3 ---------------------------------

// The library wraps EKF3's heading; the linear models unwrap it, so that
// the model the library sees is linear in an unwrapped heading. The
// library's heading unwrapped is tracked here: a prediction's is what
// lin_motion computed; an update's is the wrapped result taken at the turn
// nearest the prediction's plus the reference's change of heading (0 when
// the reference has none to give). forward_turn's heading needs no
// tracking: its model is periodic and its measured heading a wrapped
// residual.
typedef struct lin_ctx {
    const gr_scen *sc;
    gr_real theta; // the library's heading, unwrapped
} lin_ctx;

static inline gr_real unwrap_ld(gf_real th, gr_real near)
{
    const gr_real two_pi = 6.283185307179586476925L;
    gr_real k = (gr_real)floor((double)((near - (gr_real)th) / two_pi) + 0.5);
    return (gr_real)th + k * two_pi;
}

static inline gf_real unwrap(gf_real th, const lin_ctx *c)
{
    return (gf_real)unwrap_ld(th, c->theta);
}

static inline gf_status lin_motion(void *ctx, const gf_vec3 *mu,
                                   const gf_real *u, gf_vec3 *mu_bar,
                                   gf_mat3 *G)
{
    lin_ctx *c = ctx;
    (void)u;
    gf_real x[3] = {mu->v[0], mu->v[1], unwrap(mu->v[2], c)};
    for (int i = 0; i < 3; i++) {
        gf_real s = c->sc->c[i];
        for (int j = 0; j < 3; j++) {
            s += c->sc->A[i][j] * x[j];
            G->m[i][j] = c->sc->A[i][j];
        }
        mu_bar->v[i] = s;
    }
    ((lin_ctx *)ctx)->theta = (gr_real)mu_bar->v[2];
    return GF_OK;
}

static inline gf_status lin_meas(void *ctx, const gf_vec3 *mu, gf_vec3 *z_hat,
                                 gf_mat3 *H)
{
    const lin_ctx *c = ctx;
    // forward_turn's heading is an angle: measured as it is, its residual
    // wrapped by the filter (angle_mask); the linear model's is unwrapped.
    gf_real th = c->sc->kind == GR_EKF3_TURN ? mu->v[2] : unwrap(mu->v[2], c);
    gf_real x[3] = {mu->v[0], mu->v[1], th};
    for (int i = 0; i < 3; i++) {
        gf_real s = 0;
        for (int j = 0; j < 3; j++) {
            gf_real h = i < c->sc->m ? c->sc->H[i][j] : GF_R(0.0);
            s += h * x[j];
            H->m[i][j] = h;
        }
        z_hat->v[i] = s;
    }
    return GF_OK;
}

// ---- the filter under test, whichever it is -----------------------------

typedef struct lib {
    int kind;
    int prepared; // 1: through _prepare_* and the _prepared steps
    gf_kf2 kf;
    gf_ekf3 ekf;
    lin_ctx ctx;
} lib;

static inline gf_status lib_init(lib *l, const gr_scen *sc)
{
    l->kind = sc->kind;
    l->prepared = 0;
    l->ctx.sc = sc;
    l->ctx.theta = (gr_real)sc->mu0[2];
    if (sc->kind == GR_KF2) {
        gf_vec2 mu = {{sc->mu0[0], sc->mu0[1]}};
        gf_mat2 s = {
            {{sc->S0[0][0], sc->S0[0][1]}, {sc->S0[1][0], sc->S0[1][1]}}};
        return gf_kf2_init(&l->kf, &mu, &s);
    }
    gf_vec3 mu = {{sc->mu0[0], sc->mu0[1], sc->mu0[2]}};
    gf_mat3 s;
    memcpy(s.m, sc->S0, sizeof s.m);
    return gf_ekf3_init(&l->ekf, &mu, &s);
}

static inline gf_status lib_predict(lib *l, const gr_scen *sc)
{
    if (sc->kind == GR_KF2) {
        gf_kf2_model mo;
        memset(&mo, 0, sizeof mo);
        for (int i = 0; i < 2; i++) {
            mo.c.v[i] = sc->c[i];
            for (int j = 0; j < 2; j++) {
                mo.A.m[i][j] = sc->A[i][j];
                mo.R.m[i][j] = sc->R[i][j];
            }
        }
        if (l->prepared) {
            gf_kf2_pmodel pm;
            const gf_status st = gf_kf2_prepare_model(&pm, &mo);
            return st != GF_OK ? st
                               : gf_kf2_predict_prepared(&l->kf, &pm, NULL);
        }
        return gf_kf2_predict(&l->kf, &mo, NULL);
    }
    gf_ekf3_motion mo;
    memset(&mo, 0, sizeof mo);
    memcpy(mo.R.m, sc->R, sizeof mo.R.m);
    const gf_real *u = NULL;
    if (sc->kind == GR_EKF3_TURN) {
        mo.g = gf_ekf3_motion_forward_turn;
        u = sc->u;
    } else {
        mo.g = lin_motion;
        mo.ctx = &l->ctx;
    }
    if (l->prepared) {
        gf_ekf3_pmotion pm;
        const gf_status st = gf_ekf3_prepare_motion(&pm, &mo);
        return st != GF_OK ? st : gf_ekf3_predict_prepared(&l->ekf, &pm, u);
    }
    return gf_ekf3_predict(&l->ekf, &mo, u);
}

static inline gf_status lib_update(lib *l, const gr_scen *sc,
                                   const gf_real z[3], gf_real gate,
                                   gf_innovation *info)
{
    if (sc->kind == GR_KF2) {
        gf_kf2_meas me;
        memset(&me, 0, sizeof me);
        me.m = (unsigned)sc->m;
        for (int i = 0; i < sc->m; i++) {
            for (int j = 0; j < 2; j++) {
                me.C.m[i][j] = sc->H[i][j];
            }
            for (int j = 0; j < sc->m; j++) {
                me.Q.m[i][j] = sc->Q[i][j];
            }
        }
        me.gate = gate;
        gf_vec2 zz = {{z[0], z[1]}};
        if (l->prepared) {
            gf_kf2_pmeas pq;
            const gf_status st = gf_kf2_prepare_meas(&pq, &me);
            return st != GF_OK ? st
                               : gf_kf2_update_prepared(&l->kf, &pq, &zz, info);
        }
        return gf_kf2_update(&l->kf, &me, &zz, info);
    }
    gf_ekf3_meas me;
    memset(&me, 0, sizeof me);
    me.m = (unsigned)sc->m;
    me.h = lin_meas;
    me.ctx = &l->ctx;
    for (int i = 0; i < sc->m; i++) {
        for (int j = 0; j < sc->m; j++) {
            me.Q.m[i][j] = sc->Q[i][j];
        }
    }
    me.gate = gate;
    me.angle_mask = gr_angle_row(sc) >= 0 ? 1u << gr_angle_row(sc) : 0u;
    gf_vec3 zz = {{z[0], z[1], z[2]}};
    if (l->prepared) {
        gf_ekf3_pmeas pq;
        const gf_status st = gf_ekf3_prepare_meas(&pq, &me);
        return st != GF_OK ? st
                           : gf_ekf3_update_prepared(&l->ekf, &pq, &zz, info);
    }
    return gf_ekf3_update(&l->ekf, &me, &zz, info);
}

// Bit for bit the same belief.
static inline int same_belief(const lib *a, const lib *b)
{
    return a->kind == GR_KF2 ? memcmp(&a->kf, &b->kf, sizeof a->kf) == 0
                             : memcmp(&a->ekf, &b->ekf, sizeof a->ekf) == 0;
}

// The belief in long double; 1 if it is accepted back by init.
static inline int lib_belief(const lib *l, gr_real mu[3], gr_mat P)
{
    memset(P, 0, sizeof(gr_mat));
    mu[2] = 0;
    if (l->kind == GR_KF2) {
        gf_mat2 sigma;
        if (gf_kf2_cov(&l->kf, &sigma) != GF_OK) {
            return 0;
        }
        for (int i = 0; i < 2; i++) {
            mu[i] = (gr_real)l->kf.mu.v[i];
            for (int j = 0; j < 2; j++) {
                P[i][j] = (gr_real)sigma.m[i][j];
            }
        }
        gf_kf2 t;
        return gf_kf2_init(&t, &l->kf.mu, &sigma) == GF_OK;
    }
    gf_mat3 sigma;
    if (gf_ekf3_cov(&l->ekf, &sigma) != GF_OK) {
        return 0;
    }
    for (int i = 0; i < 3; i++) {
        mu[i] = (gr_real)l->ekf.mu.v[i];
        for (int j = 0; j < 3; j++) {
            P[i][j] = (gr_real)sigma.m[i][j];
        }
    }
    gf_ekf3 t;
    return gf_ekf3_init(&t, &l->ekf.mu, &sigma) == GF_OK;
}

#endif
