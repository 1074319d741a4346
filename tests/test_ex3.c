// SPDX-License-Identifier: MIT
// Exercise 3 (docs/exercises.md) as a property test: the prediction step
// of the Kalman filter is what happens to samples. Draw
// x_{t-1} ~ N(mu, Sigma) and eps ~ N(0, R), push them through
// x_t = A x_{t-1} + B u + eps, and the sample mean and covariance must
// match gf_kf2_predict's mu_bar = A mu + B u and
// Sigma_bar = A Sigma A^T + R within their sampling error.
//
// The bound, stated once: with N samples from N(m, S), the sample mean's
// entry i has standard error sqrt(S_ii / N) and the sample covariance's
// entry (i, j) has standard error sqrt((S_ij^2 + S_ii S_jj) / N) (Gaussian
// fourth moments). Every check allows SAMPLING_K = 4.5 standard errors: a
// correct filter fails one check with probability 6.8e-6, five checks per
// run under 4e-5. The generator's seed is fixed, so the run is reproducible.
#include "gf_test.h"

#define SAMPLING_K 4.5
#define N_SAMPLES 100000
#define SEED 2024u

// Exercise 1's car, with a control this time: u is an acceleration,
// B = ((0.5 0) (1 0)); R = G G^T, G = (0.5, 1)^T (rank one).
static const gf_kf2_model ex1 = {
    {{{1, 1}, {0, 1}}},
    {{{GF_R(0.5), 0}, {1, 0}}},
    {{{GF_R(0.25), GF_R(0.5)}, {GF_R(0.5), 1}}},
    {{0, 0}},
};

// Sample moments of x_t = A x + B u + eps, x ~ N(mu, Sigma), eps ~ N(0, R).
static void sample_moments(const gf_kf2_model *model, const gf_vec2 *mu,
                           const gf_mat2 *sigma, const gf_vec2 *u,
                           double mean[2], double cov[2][2])
{
    // 2-D draws as 3-D ones with a zero third variance, through the
    // library's semidefinite square root (R is rank one).
    const gf_vec3 mu3 = {{mu->v[0], mu->v[1], 0}}, zero3 = {{0, 0, 0}};
    const gf_mat3 s3 = {{{sigma->m[0][0], sigma->m[0][1], 0},
                         {sigma->m[1][0], sigma->m[1][1], 0},
                         {0, 0, 0}}};
    const gf_mat3 r3 = {{{model->R.m[0][0], model->R.m[0][1], 0},
                         {model->R.m[1][0], model->R.m[1][1], 0},
                         {0, 0, 0}}};
    gf_mat3 ls, lr;
    gf_rng rng;
    assert_int_equal(gf_mat3_sqrt_psd(&s3, 3, &ls), GF_OK);
    assert_int_equal(gf_mat3_sqrt_psd(&r3, 3, &lr), GF_OK);
    assert_int_equal(gf_rng_seed(&rng, SEED), GF_OK);

    double sum[2] = {0, 0}, sq[2][2] = {{0, 0}, {0, 0}};
    for (int k = 0; k < N_SAMPLES; k++) {
        gf_vec3 x, eps;
        gf_rng_mvn3(&rng, &mu3, &ls, &x);
        gf_rng_mvn3(&rng, &zero3, &lr, &eps);
        double xt[2];
        for (int i = 0; i < 2; i++) {
            // x_t = A x_{t-1} + B u + eps
            xt[i] = (double)model->A.m[i][0] * (double)x.v[0] +
                    (double)model->A.m[i][1] * (double)x.v[1] +
                    (double)model->B.m[i][0] * (double)u->v[0] +
                    (double)model->B.m[i][1] * (double)u->v[1] +
                    (double)eps.v[i];
            sum[i] += xt[i];
        }
        for (int i = 0; i < 2; i++) {
            for (int j = 0; j < 2; j++) {
                sq[i][j] += xt[i] * xt[j];
            }
        }
    }
    for (int i = 0; i < 2; i++) {
        mean[i] = sum[i] / N_SAMPLES;
    }
    for (int i = 0; i < 2; i++) {
        for (int j = 0; j < 2; j++) {
            cov[i][j] =
                (sq[i][j] - N_SAMPLES * mean[i] * mean[j]) / (N_SAMPLES - 1);
        }
    }
}

// How many standard errors the sample moments are from (m, S); the
// largest over the two mean entries and three covariance entries.
static double worst_z(const double mean[2], double cov[2][2], const gf_vec2 *m,
                      const gf_mat2 *S)
{
    double worst = 0;
    for (int i = 0; i < 2; i++) {
        double sii = (double)S->m[i][i];
        double z = fabs(mean[i] - (double)m->v[i]) / sqrt(sii / N_SAMPLES);
        worst = z > worst ? z : worst;
        for (int j = i; j < 2; j++) {
            double sij = (double)S->m[i][j], sjj = (double)S->m[j][j];
            double se = sqrt((sij * sij + sii * sjj) / N_SAMPLES);
            z = fabs(cov[i][j] - sij) / se;
            worst = z > worst ? z : worst;
        }
    }
    return worst;
}

// From a proper prior, with a control: samples agree with the formula.
static void test_prediction_matches_samples(void **state)
{
    (void)state;
    const gf_vec2 mu = {{1, -2}}, u = {{GF_R(0.3), 0}};
    const gf_mat2 sigma = {{{4, 1}, {1, 3}}};
    gf_kf2 kf;
    double mean[2], cov[2][2];
    assert_int_equal(gf_kf2_init(&kf, &mu, &sigma), GF_OK);
    assert_int_equal(gf_kf2_predict(&kf, &ex1, &u), GF_OK);
    // The formula's values, worked by hand: A mu + B u = (-0.85, -1.7),
    // A Sigma A^T + R = ((9.25 4.5) (4.5 4)).
    CHECK_CLOSE(kf.mu.v[0], -0.85);
    CHECK_CLOSE(kf.mu.v[1], -1.7);
    const gf_mat2 sigma_bar = gf_test_kf2_sigma(&kf);
    CHECK_CLOSE(sigma_bar.m[0][0], 9.25);
    CHECK_CLOSE(sigma_bar.m[0][1], 4.5);
    CHECK_CLOSE(sigma_bar.m[1][1], 4.0);

    sample_moments(&ex1, &mu, &sigma, &u, mean, cov);
    double z = worst_z(mean, cov, &kf.mu, &sigma_bar);
    print_message("  exercise 3: worst deviation %.2f standard errors "
                  "(bound %.1f, N = %d)\n",
                  z, SAMPLING_K, N_SAMPLES);
    assert_true(z <= SAMPLING_K);
}

// Exercise 1's own steps t = 1 -> 2 -> 3 (Sigma_1 = R singular, Sigma_2,
// Sigma_3 of Table 1.1): samples pushed through each step match.
static void test_table_1_1_steps_match_samples(void **state)
{
    (void)state;
    const gf_vec2 mu = {{0, 0}}, u0 = {{0, 0}};
    const gf_mat2 zero = {{{0, 0}, {0, 0}}};
    gf_kf2 kf;
    assert_int_equal(gf_kf2_init(&kf, &mu, &zero), GF_OK);
    for (int t = 1; t <= 4; t++) {
        const gf_kf2 prev = kf;
        const gf_mat2 prev_sigma = gf_test_kf2_sigma(&prev);
        assert_int_equal(gf_kf2_predict(&kf, &ex1, &u0), GF_OK);
        double mean[2], cov[2][2];
        sample_moments(&ex1, &prev.mu, &prev_sigma, &u0, mean, cov);
        const gf_mat2 sigma_bar = gf_test_kf2_sigma(&kf);
        assert_true(worst_z(mean, cov, &kf.mu, &sigma_bar) <= SAMPLING_K);
    }
    const gf_mat2 sigma_4 = gf_test_kf2_sigma(&kf);
    CHECK_CLOSE(sigma_4.m[0][0], 21.0); // Table 1.1, t = 4
}

// The check can fail: the worked solutions' equation 1.8, R = diag(0.25, 1), is
// not the noise the samples carry (the tables' R = G G^T is), and the test sees
// it: the covariance is off by many standard errors.
static void test_wrong_noise_is_detected(void **state)
{
    (void)state;
    const gf_vec2 mu = {{1, -2}}, u = {{GF_R(0.3), 0}};
    const gf_mat2 sigma = {{{4, 1}, {1, 3}}};
    gf_kf2_model eq18 = ex1;
    eq18.R.m[0][1] = eq18.R.m[1][0] = 0;
    gf_kf2 kf;
    double mean[2], cov[2][2];
    assert_int_equal(gf_kf2_init(&kf, &mu, &sigma), GF_OK);
    assert_int_equal(gf_kf2_predict(&kf, &eq18, &u), GF_OK);
    sample_moments(&ex1, &mu, &sigma, &u, mean, cov);
    const gf_mat2 sigma_bar = gf_test_kf2_sigma(&kf);
    double z = worst_z(mean, cov, &kf.mu, &sigma_bar);
    print_message("  equation 1.8's R: %.1f standard errors off\n", z);
    assert_true(z > 3 * SAMPLING_K);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_prediction_matches_samples),
        cmocka_unit_test(test_table_1_1_steps_match_samples),
        cmocka_unit_test(test_wrong_noise_is_detected),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
