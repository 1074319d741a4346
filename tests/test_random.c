// SPDX-License-Identifier: MIT
// KF2 and EKF3 against a reference Joseph filter in long double, on seeded
// random scenarios (tests/gf_ref.h): prior/noise variance ratios up to
// GR_RATIO_MAX, prior correlation forms with condition numbers up to
// GR_COND_MAX, every unit scaled by 1e-3..1e3, unstable motion, rank-
// deficient R and Q, m = 1..3 with correlated Q, long runs without a
// measurement; EKF3 with the test's own linear models (so that the
// reference is exact) and with gf_ekf3_motion_forward_turn.
//
// Asserted, step by step:
// - every accepted belief is positive semidefinite: the correlation form's
//   smallest eigenvalue >= -PSD_TOL, tested in long double by gr_psd
//   (independent of the library), and gf_kf2_init / gf_ekf3_init accept it
//   back;
// - every prediction and every well-posed update is accepted. Well-posed:
//   every input finite, the prior the filter holds, Q positive definite
//   with its correlation form's eigenvalues >= 1 / GR_QCOND (1e-3, far
//   above any rounding of gf_real), gate off or above the NIS, and every
//   quantity of the update (S, K, the posterior) within the range of
//   gf_real by construction. S >= Q > 0 is then never singular;
// - the errors against the reference, |Sigma_ij - ref_ij| / sqrt(ref_ii
//   ref_jj) and |mu_i - ref_i| / sqrt(ref_Sigma_ii) (the heading on the
//   circle), and |NIS - ref NIS|, against the bound, stated once per build
//   by its formula in that build's u (2^-24 float, 2^-53 double): BOUND_C
//   times the spread of two perturbed copies of the reference (the error
//   the scenario's conditioning gives a filter computing in gf_real), or
//   TB_C times the error of a textbook Joseph filter in gf_real on the
//   same step, whichever is larger (see BOUND_C and docs/testing.md). The
//   reference updates in the batch form and the library sequentially, so
//   these comparisons are also the test that the two forms agree. What is
//   asserted of them is the accuracy target on these scenarios: the
//   library no worse than the textbook filter, i.e. no more steps over the
//   bound than the textbook filter has, and a worst error / bound no
//   larger than the textbook filter's; steps over the bound stay below
//   OVER_MAX of the steps compared (every one is printed with GR_ALL=1 in
//   the environment); the NIS over its first-order bound on at most
//   OVER_MAX of the steps too;
// - the gate applies to the total NIS: a gate at twice the reference's NIS
//   accepts, one at half refuses with GF_ERR_GATED and the belief
//   bit-for-bit unchanged (only where the NIS's bound is below a quarter
//   of it);
// - every refused call leaves the belief bit-for-bit unchanged.
// Per build and family, the worst and median errors print on stdout,
// beside the textbook filter's and the long-double sequential form's
// (rows whitened by Q's L D L^T factor) excess over the bound, which are
// reported, not asserted.
#include <stdlib.h>

#include "gf_test.h"
#include "gf_ref_lib.h"

// The firmware images (bare-metal Arm, run under qemu: no __linux__) run
// 150 scenarios per family instead of 1000: the long-double reference is
// software double there (about 12 s under qemu on a loaded machine).
#if defined(__arm__) && !defined(__linux__)
#define SCENARIOS 150
#define LONG_RUN 100
#else
#define SCENARIOS 1000
#define LONG_RUN 100
#endif

#define SEED 0x9a55f117u

// A belief is PSD within 64 ulps of 1 in the correlation form: the
// library's own acceptance tolerance (GF_PD_RTOL), so that what a filter
// returns it also takes back.
#define PSD_TOL (64.0 * (double)GF_REAL_EPSILON)

// ---- the reference and its perturbed copies ----------------------------

// The bound on an error: BOUND_C times the spread of two perturbed copies
// of the reference (gf_ref.h's gr_filt: every input and every stored
// belief perturbed by 1 +- u, u = gf_real's unit roundoff) around it, and
// never below BOUND_C u. BOUND_C = 64: each step of a filter in gf_real
// rounds each entry along a chain of about n + m <= 6 products and sums
// twice over (prediction, then update), where the copies are perturbed
// once per input and per stored entry: a factor of 2 (n + m) ~ 12, and a
// factor of 4 for the two copies' signs missing the worst direction, 48,
// rounded up to a power of two. A bound of 1 or more leaves no digit to
// check: such steps are counted as vacuous and not compared.
#define BOUND_C 64.0
// The share of compared steps that may exceed the bound (float: 1 in
// 10,000 seen, double: about 1 in 200, where the perturbed copies most
// under-rate the conditioning): 2%.
#define OVER_MAX 0.02
// Where the two copies miss the conditioning (a structure their two
// directions of perturbation do not excite; the textbook filter then
// exceeds 64 times their spread too, which the test prints), the bound is
// TB_C times the error of the textbook Joseph filter in gf_real (gr_tb) on
// the same step, while that filter is alive: the accuracy target (no worse
// than a textbook filter), with a factor of 16 for the difference of two
// algorithms' rounding on one step.
#define TB_C 16.0

typedef struct refs {
    gr_filt ref, pa, pb, seq;
} refs;

static void refs_init(refs *r, const gr_scen *sc, unsigned index)
{
    gr_filt_init(&r->ref, sc, 0, 0);
    gr_filt_init(&r->pa, sc, GR_U, 0x5eed0001ull + index);
    gr_filt_init(&r->pb, sc, -GR_U, 0x5eed8001ull + index);
    r->seq = r->ref;
}

static void refs_predict(refs *r, gr_scen *sc)
{
    gr_filt *f[4] = {&r->ref, &r->pa, &r->pb, &r->seq};
    for (int i = 0; i < 4; i++) {
        gr_predict_scen(f[i], sc);
    }
}

// The bounds on the errors of Sigma, mu and the NIS at this step.
typedef struct bounds {
    double s, m, nis;
} bounds;

static bounds bounds_of(refs *r, int angle)
{
    double sa, ma, sb, mb;
    gr_errors(&r->ref, NULL, r->pa.mu, r->pa.P, angle, &sa, &ma);
    gr_errors(&r->ref, NULL, r->pb.mu, r->pb.P, angle, &sb, &mb);
    bounds b;
    b.s = BOUND_C * fmax(fmax(sa, sb), GR_U);
    b.m = BOUND_C * fmax(fmax(ma, mb), GR_U);
    b.nis = 0;
    return b;
}

// ---- tallies -----------------------------------------------------------

typedef struct tally {
    unsigned scenarios, compared, vacuous;
    unsigned not_psd, not_taken_back, refused_wp, refused_other;
    unsigned pred_refused, over_bound, nis_over, gate_wrong, changed;
    unsigned seq_over;
    double worst_s, worst_m, worst_ratio;
    // The textbook Joseph filter in gf_real on the same steps (gr_tb):
    // not asserted, printed beside the library as the bound's calibration.
    unsigned tb_refused_wp, tb_over, tb_not_psd;
    double tb_worst_s, tb_worst_m, tb_worst_ratio;
} tally;

// Prints the first three of each kind of failure (every one with GR_ALL=1
// in the environment) and counts them.
static void fail_note(unsigned *counter, const char *what, const gr_scen *sc,
                      unsigned index, int step, double got, double bound)
{
    if (++*counter <= 3 || getenv("GR_ALL")) {
        print_message("  %s: family %d scenario %u step %d m %d: %.3g "
                      "(bound %.3g)\n",
                      what, sc->kind, index, step, sc->m, got, bound);
    }
}

// GR_TRACE=index in the environment prints the steps of scenario `index`
// of every family, and the matrices behind its failures in hex.
static void trace_matrix(const char *what, int n, gr_mat M)
{
    for (int i = 0; i < n; i++) {
        print_message("  %s %a %a %a\n", what, (double)M[i][0], (double)M[i][1],
                      (double)M[i][2]);
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, unsigned n)
{
    if (n == 0) {
        return 0;
    }
    qsort(v, n, sizeof *v, cmp_double);
    return v[n / 2];
}

static double per_s[SCENARIOS], per_m[SCENARIOS];

// The references and the matrices of a step: file-scope, as the emulated
// target's stack (16 KiB) is small.
static refs r_run, r_next;
static gr_mat m_lib, m_tb, m_aux;

// FNV-1a over the bytes of the scenarios' inputs (the models and the prior,
// before the truth): the same hash on two machines means the same
// scenarios, whatever their libm (the generator calls exp, log, cos and
// sqrt in double).
static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++) {
        h = (h ^ b[i]) * 0x100000001b3ull;
    }
    return h;
}

static void run_family(int kind, tally *t)
{
    memset(t, 0, sizeof *t);
    unsigned ncmp = 0;
    uint64_t inputs = 0xcbf29ce484222325ull;
    int trace = getenv("GR_TRACE") ? atoi(getenv("GR_TRACE")) : -1;
    const int angle = kind != GR_KF2;
    for (unsigned index = 0; index < SCENARIOS; index++) {
        gr_scen sc;
        gr_scen_make(&sc, kind, SEED, index, LONG_RUN);
        if (index < 150) { // the count both host and target run
            inputs = fnv(inputs, &sc, offsetof(gr_scen, x));
        }
        refs_init(&r_run, &sc, index);
        lib l;
        assert_int_equal(lib_init(&l, &sc), GF_OK);
        gr_tb tb;
        gr_tb_init(&tb, &sc);
        int tb_live = 1;
        t->scenarios++;
        double ws = 0, wm = 0;
        int total = sc.pre + sc.steps;
        for (int step = 0; step < total; step++) {
            lib before = l;
            gf_status st = lib_predict(&l, &sc);
            if (st != GF_OK) {
                fail_note(&t->pred_refused, "prediction refused", &sc, index,
                          step, (double)st, 0);
                if (trace == (int)index) {
                    gr_real bm[GR_N];
                    (void)lib_belief(&before, bm, m_lib);
                    for (int i = 0; i < 3; i++) {
                        for (int j = 0; j < 3; j++) {
                            m_aux[i][j] = (gr_real)sc.R[i][j];
                        }
                    }
                    trace_matrix("prior", sc.n, m_lib);
                    trace_matrix("R", sc.n, m_aux);
                }
                assert_true(same_belief(&before, &l));
                break;
            }
            gr_tb_predict(&tb, &sc);
            gr_scen_move(&sc);
            refs_predict(&r_run, &sc);
            int upd = step >= sc.pre;
            gf_innovation info;
            gr_real ref_nis = 0;
            double nis_bound = 0;
            if (upd) {
                gf_real z[3] = {0, 0, 0};
                gr_scen_measure(&sc, z);
                r_next = r_run;
                gr_real na = 0, nb = 0;
                int ref_ok = gr_update_scen(&r_next.ref, &sc, z, &ref_nis);
                int pa_ok = gr_update_scen(&r_next.pa, &sc, z, &na);
                int pb_ok = gr_update_scen(&r_next.pb, &sc, z, &nb);
                nis_bound = BOUND_C * fmax(fmax(fabs((double)(na - ref_nis)),
                                                fabs((double)(nb - ref_nis))),
                                           GR_U * (double)ref_nis);
                if (!pa_ok || !pb_ok) {
                    nis_bound = (double)INFINITY;
                }
                // The gate: off, or (one update in four) at twice or half
                // the reference's NIS, when the NIS's bound is far smaller.
                gf_real gate = 0;
                int gmode = 0;
                double nr = (double)ref_nis;
                if (ref_ok && (step & 3) == 3 && nis_bound < 0.25 * nr &&
                    nr > 1e-6) {
                    gmode = ((index + (unsigned)step) & 1) ? 1 : 2;
                    gate = (gf_real)(gmode == 1 ? 2.0 * nr : 0.5 * nr);
                }
                before = l;
                st = lib_update(&l, &sc, z, gate, &info);
                if (gmode == 2 && (st == GF_OK || st == GF_ERR_GATED)) {
                    if (st != GF_ERR_GATED) {
                        fail_note(&t->gate_wrong, "gate below the NIS passed",
                                  &sc, index, step, (double)st, 0);
                    }
                    if (!same_belief(&before, &l)) {
                        fail_note(&t->changed, "gated call changed belief", &sc,
                                  index, step, 0, 0);
                    }
                    continue; // the belief stays the prior: so do the refs
                }
                if (st != GF_OK) {
                    if (!same_belief(&before, &l)) {
                        fail_note(&t->changed, "refusal changed belief", &sc,
                                  index, step, (double)st, 0);
                    }
                    if (sc.q_pd) {
                        fail_note(&t->refused_wp, "well-posed update refused",
                                  &sc, index, step, (double)st, 0);
                    } else {
                        t->refused_other++;
                    }
                    continue; // both keep the prior
                }
                {
                    gr_real dth = r_next.ref.mu[2] - r_run.ref.mu[2];
                    if (!ref_ok || !(dth > -1e9L && dth < 1e9L)) {
                        dth = 0;
                    }
                    l.ctx.theta = unwrap_ld(l.ekf.mu.v[2], l.ctx.theta + dth);
                }
                if (tb_live && !gr_tb_update(&tb, &sc, z)) {
                    tb_live = 0;
                    t->tb_refused_wp += (unsigned)sc.q_pd;
                }
                if (!ref_ok) {
                    // Only with a rank-deficient Q: the reference's S is
                    // singular and the library accepted. Stop comparing.
                    sc.compare = 0;
                } else {
                    // The long-double sequential form from the same prior,
                    // against the batch form: not asserted, reported (how
                    // much the sequential form itself loses).
                    gr_real nis_seq = 0;
                    r_next.seq = r_run.ref;
                    if (gr_update_seq(&r_next.seq, sc.m, (const gf_real *)sc.H,
                                      3, (const gf_real *)sc.Q, 3, z,
                                      &nis_seq)) {
                        double es, em;
                        gr_errors(&r_next.ref, NULL, r_next.seq.mu,
                                  r_next.seq.P, angle, &es, &em);
                        bounds bq = bounds_of(&r_next, angle);
                        double scale = GR_U_REF / GR_U;
                        if (es > bq.s * scale || em > bq.m * scale) {
                            t->seq_over++;
                        }
                    }
                    r_run = r_next;
                }
                if (!pa_ok || !pb_ok) {
                    sc.compare = 0;
                }
            }
            gr_real mu[GR_N], (*P)[GR_N] = m_lib;
            int back = lib_belief(&l, mu, P);
            if (trace == (int)index) {
                print_message("trace %d/%u step %d (heading track %g): "
                              "status %d, mu %g %g %g, reference %g %g %g\n",
                              kind, index, step, (double)l.ctx.theta, (int)st,
                              (double)mu[0], (double)mu[1], (double)mu[2],
                              (double)r_run.ref.mu[0], (double)r_run.ref.mu[1],
                              (double)r_run.ref.mu[2]);
            }
            if (!gr_psd(sc.n, P, PSD_TOL)) {
                fail_note(&t->not_psd, "belief not PSD", &sc, index, step, 0,
                          0);
                if (trace == (int)index) {
                    trace_matrix("Sigma", sc.n, P);
                }
            }
            if (!back) {
                fail_note(&t->not_taken_back, "belief refused by init", &sc,
                          index, step, 0, 0);
                if (trace == (int)index) {
                    trace_matrix("Sigma", sc.n, P);
                }
            }
            if (!sc.compare) {
                continue;
            }
            bounds b = bounds_of(&r_run, angle);
            if (!(b.s < 1.0 && b.m < 1.0)) {
                t->vacuous++; // the conditioning leaves no digit to check
                continue;
            }
            double es, em;
            double tes = -1, tem = -1;
            if (tb_live) {
                gr_real tmu[GR_N], (*tP)[GR_N] = m_tb;
                for (int i = 0; i < sc.n; i++) {
                    tmu[i] = (gr_real)tb.mu[i];
                    for (int j = 0; j < sc.n; j++) {
                        tP[i][j] = (gr_real)tb.P[i][j];
                    }
                }
                gr_errors(&r_run.ref, NULL, tmu, tP, 0, &tes, &tem);
                if (!gr_psd(sc.n, tP, PSD_TOL)) {
                    t->tb_not_psd++;
                }
                t->tb_worst_s = fmax(tes, t->tb_worst_s);
                t->tb_worst_m = fmax(tem, t->tb_worst_m);
                t->tb_worst_ratio =
                    fmax(fmax(tes / b.s, tem / b.m), t->tb_worst_ratio);
                t->tb_over += tes > b.s || tem > b.m;
                // The target beside the bound: no worse than TB_C times
                // the textbook filter on the same step.
                b.s = fmax(b.s, TB_C * tes);
                b.m = fmax(b.m, TB_C * tem);
            }
            gr_errors(&r_run.ref, NULL, mu, P, angle, &es, &em);
            if (trace == (int)index) {
                print_message("trace %d/%u step %d: errors Sigma %.3g mu %.3g, "
                              "textbook %.3g %.3g, bound %.3g %.3g\n",
                              kind, index, step, es, em, tes, tem, b.s, b.m);
            }
            t->compared++;
            ws = fmax(es, ws);
            wm = fmax(em, wm);
            t->worst_ratio = fmax(fmax(es / b.s, em / b.m), t->worst_ratio);
            if (es > b.s || em > b.m) {
                fail_note(&t->over_bound, "error over the bound", &sc, index,
                          step, es / b.s > em / b.m ? es : em,
                          es / b.s > em / b.m ? b.s : b.m);
            }
            if (upd) {
                double dn = fabs((double)info.nis - (double)ref_nis);
                if (dn > nis_bound) {
                    fail_note(&t->nis_over, "NIS over its bound", &sc, index,
                              step, dn, nis_bound);
                }
            }
        }
        if (sc.compare) {
            per_s[ncmp] = ws;
            per_m[ncmp] = wm;
            ncmp++;
            t->worst_s = fmax(ws, t->worst_s);
            t->worst_m = fmax(wm, t->worst_m);
        }
    }
    static const char *const names[] = {"KF2", "EKF3 linear",
                                        "EKF3 forward_turn"};
    double med_s = median(per_s, ncmp), med_m = median(per_m, ncmp);
    print_message("%s (%s, u = %.3g): %u scenarios (the first 150's "
                  "inputs hash to %08x), "
                  "%u steps compared (%u with a vacuous bound)\n",
                  names[kind], sizeof(gf_real) == 4 ? "float" : "double", GR_U,
                  t->scenarios, (unsigned)(inputs >> 32), t->compared,
                  t->vacuous);
    print_message("  Sigma error worst %.3g median %.3g; mu error worst %.3g "
                  "median %.3g; worst error / bound %.3g\n",
                  t->worst_s, med_s, t->worst_m, med_m, t->worst_ratio);
    print_message("  refused: %u well-posed, %u other (rank-deficient Q); "
                  "predictions refused %u\n",
                  t->refused_wp, t->refused_other, t->pred_refused);
    print_message("  over the bound: %u steps; the long-double sequential "
                  "form over its own bound: %u updates\n",
                  t->over_bound, t->seq_over);
    print_message("  textbook Joseph in gf_real: Sigma worst %.3g, mu worst "
                  "%.3g, worst error / bound %.3g, %u steps over the bound, "
                  "%u not PSD, %u well-posed refused\n",
                  t->tb_worst_s, t->tb_worst_m, t->tb_worst_ratio, t->tb_over,
                  t->tb_not_psd, t->tb_refused_wp);
}

static void check_tally(const tally *t)
{
    assert_int_equal(t->pred_refused, 0);
    assert_int_equal(t->refused_wp, 0);
    assert_int_equal(t->not_psd, 0);
    assert_int_equal(t->not_taken_back, 0);
    assert_int_equal(t->changed, 0);
    assert_int_equal(t->gate_wrong, 0);
    assert_true(t->over_bound <= t->tb_over);
    assert_true(t->worst_ratio <= t->tb_worst_ratio);
    assert_true((double)t->over_bound <= OVER_MAX * (double)t->compared);
    assert_true((double)t->nis_over <= OVER_MAX * (double)t->compared);
}

static void random_kf2(void **state)
{
    (void)state;
    tally t;
    run_family(GR_KF2, &t);
    check_tally(&t);
}

static void random_ekf3_linear(void **state)
{
    (void)state;
    tally t;
    run_family(GR_EKF3_LIN, &t);
    check_tally(&t);
}

static void random_ekf3_turn(void **state)
{
    (void)state;
    tally t;
    run_family(GR_EKF3_TURN, &t);
    check_tally(&t);
}

// The prepared path against the plain one, bit for bit: on every scenario
// of every family, two filters, one through gf_kf2_predict/update and
// gf_ekf3_predict/update, one through the _prepare_* calls and the
// _prepared steps, get the same inputs (gates included: every fourth
// update gated at half the plain NIS of the step before, so that gated
// steps are compared too); every status, belief and info must be the same
// bytes.
static void prepared_same_as_plain(void **state)
{
    (void)state;
    const int kinds[3] = {GR_KF2, GR_EKF3_LIN, GR_EKF3_TURN};
    unsigned calls = 0, gated = 0, refused = 0;
    for (int f = 0; f < 3; f++) {
        for (unsigned index = 0; index < SCENARIOS / 4u; index++) {
            gr_scen sc;
            gr_scen_make(&sc, kinds[f], SEED, index, LONG_RUN);
            lib a, b;
            assert_int_equal(lib_init(&a, &sc), GF_OK);
            assert_int_equal(lib_init(&b, &sc), GF_OK);
            b.prepared = 1;
            gf_real last_nis = 0;
            for (int step = 0; step < sc.pre + sc.steps; step++) {
                gf_status sa = lib_predict(&a, &sc);
                gf_status sb = lib_predict(&b, &sc);
                calls++;
                assert_int_equal(sa, sb);
                assert_true(same_belief(&a, &b));
                if (sa != GF_OK) {
                    break;
                }
                gr_scen_move(&sc);
                if (step < sc.pre) {
                    continue;
                }
                gf_real z[3] = {0, 0, 0};
                gr_scen_measure(&sc, z);
                const gf_real gate =
                    (step & 3) == 3 ? GF_R(0.5) * last_nis : GF_R(0.0);
                gf_innovation ia, ib;
                memset(&ia, 0, sizeof ia);
                memset(&ib, 0, sizeof ib);
                sa = lib_update(&a, &sc, z, gate, &ia);
                sb = lib_update(&b, &sc, z, gate, &ib);
                calls++;
                assert_int_equal(sa, sb);
                assert_true(same_belief(&a, &b));
                assert_memory_equal(&ia, &ib, sizeof ia);
                gated += sa == GF_ERR_GATED;
                refused += sa != GF_OK && sa != GF_ERR_GATED;
                if (sa == GF_OK) {
                    last_nis = ia.nis;
                    a.ctx.theta = unwrap_ld(a.ekf.mu.v[2], a.ctx.theta);
                    b.ctx.theta = unwrap_ld(b.ekf.mu.v[2], b.ctx.theta);
                }
            }
        }
    }
    print_message("prepared and plain paths: %u calls the same bit for bit "
                  "(%u gated, %u refused)\n",
                  calls, gated, refused);
    assert_true(gated > 0u && refused > 0u);
}

// The prediction's mean rounded once: a model that carries each state
// over (A_ii = 1) and adds small terms to it (A_ij mu_j, c_i, (B u)_i on a
// grid fine enough that their sum is exact in float) must give
// mu_bar_i = the exact sum rounded to gf_real once, in KF2 and in gf_kf:
// the state's own term is added last. Seeded data: a position in
// +-[256, 512) on its float grid, a velocity below 2 in magnitude, dt in
// eighths, c and u below 1 on the 2^-22 grid (every product and partial
// sum of the small terms exact in float; the long double sum exact). The
// order that adds the large term first rounds two or three times, and the
// count of cases where it would differ shows the data tells them apart.
static void predict_mean_rounded_once(void **state)
{
    (void)state;
    gr_rng rng = {0x6d75626172ull};
    const long double g22 = 0x1.0p-22L;
    unsigned other_order_differs = 0;
    const unsigned cases = 2000;
    for (unsigned k = 0; k < cases; k++) {
        const gf_real dt = (gf_real)(gr_below(&rng, 7u) + 1u) * GF_R(0.125);
        gf_real x = (gf_real)(256.0L + gr_below(&rng, 1u << 23) * 0x1.0p-15L);
        if (gr_below(&rng, 2u)) {
            x = -x;
        }
        const gf_real v =
            (gf_real)(((long double)gr_below(&rng, 1u << 21) - 0x1.0p20L) *
                      0x1.0p-19L);
        gf_real cu[4];
        for (int i = 0; i < 4; i++) {
            cu[i] =
                (gf_real)(((long double)gr_below(&rng, 1u << 23) - 0x1.0p22L) *
                          g22);
        }
        const gf_kf2_model mo = {
            .A = {{{1, dt}, {0, 1}}},
            .B = {{{1, 0}, {0, 1}}},
            .R = {{{GF_R(0.01), 0}, {0, GF_R(0.01)}}},
            .c = {{cu[0], cu[1]}},
        };
        const gf_vec2 u = {{cu[2], cu[3]}};
        const gf_real want[2] = {(gf_real)((long double)x + (long double)cu[0] +
                                           (long double)dt * (long double)v +
                                           (long double)cu[2]),
                                 (gf_real)((long double)v + (long double)cu[1] +
                                           (long double)cu[3])};
        // the large term first, as a plain A mu + c + B u would
        volatile gf_real first = x + dt * v;
        first = first + cu[0];
        first = first + cu[2];
        other_order_differs += first != want[0];

        const gf_vec2 mu = {{x, v}};
        const gf_mat2 sigma = {{{1, 0}, {0, 1}}};
        gf_kf2 kf;
        assert_int_equal(gf_kf2_init(&kf, &mu, &sigma), GF_OK);
        assert_int_equal(gf_kf2_predict(&kf, &mo, &u), GF_OK);
        assert_true(kf.mu.v[0] == want[0] && kf.mu.v[1] == want[1]);

        gf_kf_work work;
        gf_kf g;
        const gf_kf_model gm = {2u, mo.A.m[0], mo.B.m[0], mo.R.m[0], mo.c.v};
        assert_int_equal(gf_kf_init(&g, 2u, mu.v, sigma.m[0], &work), GF_OK);
        assert_int_equal(gf_kf_predict(&g, &gm, u.v, &work), GF_OK);
        assert_true(g.mu[0] == want[0] && g.mu[1] == want[1]);
    }
    print_message("predicted means rounded once in %u cases; the large term "
                  "first would round %u of them differently\n",
                  cases, other_order_differs);
#ifdef GF_SINGLE_PRECISION
    assert_true(other_order_differs > cases / 10u);
#endif
}

// The reference on a case whose answer is known exactly: prior diag(4,
// 9), x measured with Q = 1: S = 5, K = (4/5, 0), Sigma = diag(4/5, 9),
// NIS = z^2 / 5; its sequential form; its PSD test.
static void reference_itself(void **state)
{
    (void)state;
    gr_scen sc;
    memset(&sc, 0, sizeof sc);
    sc.kind = GR_KF2;
    sc.n = 2;
    sc.m = 1;
    sc.S0[0][0] = 4;
    sc.S0[1][1] = 9;
    sc.H[0][0] = 1;
    sc.Q[0][0] = 1;
    gr_filt f;
    gr_filt_init(&f, &sc, 0, 0);
    gf_real z[3] = {2, 0, 0};
    gr_real nis = 0;
    assert_true(gr_update_scen(&f, &sc, z, &nis));
    const double tiny = 16 * (double)LDBL_EPSILON;
    assert_true(fabs((double)(f.P[0][0] - 0.8L)) < tiny);
    assert_true(fabs((double)(f.mu[0] - 1.6L)) < tiny);
    assert_true(fabs((double)(nis - 0.8L)) < tiny);
    assert_true(f.P[1][1] == 9 && f.P[0][1] == 0);
    // The sequential form equals the batch form on a well-conditioned m = 3
    // update with a correlated Q.
    gr_scen s3;
    memset(&s3, 0, sizeof s3);
    s3.kind = GR_EKF3_LIN;
    s3.n = 3;
    s3.m = 3;
    gf_real p0[3][3] = {{4, 1, 0}, {1, 3, GF_R(0.5)}, {0, GF_R(0.5), 2}};
    gf_real h[3][3] = {{1, 0, 0}, {GF_R(0.5), 1, 0}, {0, 1, 1}};
    gf_real q[3][3] = {{1, GF_R(0.5), GF_R(0.25)},
                       {GF_R(0.5), 2, GF_R(0.5)},
                       {GF_R(0.25), GF_R(0.5), 1}};
    memcpy(s3.S0, p0, sizeof p0);
    memcpy(s3.H, h, sizeof h);
    memcpy(s3.Q, q, sizeof q);
    gr_filt *fb = &r_run.ref, *fs = &r_run.seq;
    gr_filt_init(fb, &s3, 0, 0);
    *fs = *fb;
    gf_real z3[3] = {1, -2, GF_R(0.5)};
    gr_real nb = 0, ns = 0;
    assert_true(gr_update_scen(fb, &s3, z3, &nb));
    assert_true(gr_update_seq(fs, 3, (const gf_real *)s3.H, 3,
                              (const gf_real *)s3.Q, 3, z3, &ns));
    double es, em;
    gr_errors(fb, NULL, fs->mu, fs->P, 0, &es, &em);
    assert_true(es < 1e-15 && em < 1e-15);
    assert_true(fabs((double)(nb - ns)) < 1e-15 * (double)nb);
    // The PSD test: semidefinite passes, a correlation of 1 + 1e-3 fails.
    gr_real(*a)[GR_N] = m_aux;
    memset(m_aux, 0, sizeof m_aux);
    a[0][0] = a[0][1] = a[1][0] = a[1][1] = 1;
    assert_true(gr_psd(3, a, PSD_TOL));
    a[0][1] = a[1][0] = 1.001L;
    assert_false(gr_psd(2, a, PSD_TOL));
    a[0][1] = a[1][0] = 0;
    a[2][0] = a[0][2] = 1e-30L; // a zero variance with a covariance
    assert_false(gr_psd(3, a, PSD_TOL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(reference_itself),
        cmocka_unit_test(random_kf2),
        cmocka_unit_test(random_ekf3_linear),
        cmocka_unit_test(random_ekf3_turn),
        cmocka_unit_test(prepared_same_as_plain),
        cmocka_unit_test(predict_mean_rounded_once),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
