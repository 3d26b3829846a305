/* Every entry point refuses what rsf.h says it refuses: a non-finite or out-of-range input is
 * RSF_BAD_INPUT with a message naming it (and, for the batch calls, the element), never
 * RSF_OK with a NaN or infinite result. Prints one line per call: `name -> status: message`. */
#include <math.h>
#include <stdio.h>
#include "rsf.h"

static int refused = 0, accepted = 0;

static void report(const char *name, enum RsfStatus st, double out) {
    if (st == RSF_OK) {
        accepted++;
        printf("%s -> 0 (ACCEPTED, output %g)\n", name, out);
    } else {
        refused++;
        printf("%s -> %d: %s\n", name, (int)st, rsf_last_error());
    }
}

int main(void) {
    RsfFrictionParams fp = {RSF_ABI_VERSION, RSF_FORM_CLASSIC, 0.6, 0.01, 1e-6};
    RsfStateParams sp = {RSF_ABI_VERSION, RSF_LAW_AGING, 0.015, 0.01, 0.0};
    double out = 0, d1 = 0, d2 = 0;
    const double bad_v0[] = {NAN, -1.0, 0.0, INFINITY};
    const char *bad_v0_name[] = {"psi v0=nan", "psi v0=-1", "psi v0=0", "psi v0=inf"};
    for (int k = 0; k < 4; k++) {
        out = 0;
        report(bad_v0_name[k], rsf_psi(&sp, bad_v0[k], 0.0, &out), out);
    }
    report("psi ln_theta=nan", rsf_psi(&sp, 1e-6, NAN, &out), out);
    report("psi ln_theta=inf", rsf_psi(&sp, 1e-6, INFINITY, &out), out);
    report("friction ln_v=nan", rsf_friction(&fp, NAN, 0.0, &out, &d1, &d2), out);
    report("friction psi=inf", rsf_friction(&fp, 0.0, INFINITY, &out, &d1, &d2), out);
    report("friction null output", rsf_friction(&fp, 0.0, 0.0, NULL, &d1, &d2), out);
    RsfFrictionParams bad_a = fp;
    bad_a.a = -0.01;
    report("friction a<0", rsf_friction(&bad_a, 0.0, 0.0, &out, &d1, &d2), out);
    report("rate ln_v=nan", rsf_ln_theta_rate(&sp, NAN, 0.0, &out), out);
    report("rate ln_theta=-inf", rsf_ln_theta_rate(&sp, 0.0, -INFINITY, &out), out);
    RsfStateParams bad_dc = sp;
    bad_dc.dc = 0.0;
    report("rate dc=0", rsf_ln_theta_rate(&bad_dc, 0.0, 0.0, &out), out);
    report("solve tau=nan", rsf_solve_slip_rate(&fp, 0.0, NAN, 50.0, 0.0, 0.0, &out, NULL), out);
    report("solve eta<0", rsf_solve_slip_rate(&fp, 0.0, 30.0, 50.0, -1.0, 0.0, &out, NULL), out);

    /* batches: element 2 of 4 is bad */
    RsfFrictionParams fps[4] = {fp, fp, fp, fp};
    RsfStateParams sps[4] = {sp, sp, sp, sp};
    double lv[4] = {0, 0, NAN, 0}, lt[4] = {0, 0, 0, 0}, f[4], a[4], b[4], r[4];
    report("batch_rates ln_v[2]=nan", rsf_batch_rates(4, fps, sps, lv, lt, f, a, b, r), f[2]);
    lv[2] = 0;
    lt[2] = INFINITY;
    report("batch_rates ln_theta[2]=inf", rsf_batch_rates(4, fps, sps, lv, lt, f, a, b, r), f[2]);
    lt[2] = 0;
    sps[2].version = 99;
    report("batch_rates version[2]", rsf_batch_rates(4, fps, sps, lv, lt, f, a, b, r), f[2]);
    sps[2].version = RSF_ABI_VERSION;
    report("batch_rates null", rsf_batch_rates(4, fps, sps, lv, NULL, f, a, b, r), f[2]);
    double tau[4] = {30, 30, 30, 30}, sg[4] = {50, 50, NAN, 50}, et[4] = {0, 0, 0, 0};
    double guess[4] = {0, 0, 0, 0};
    report("batch_solve sigma[2]=nan", rsf_batch_solve_slip_rate(4, fps, sps, lt, tau, sg, et, guess), guess[2]);
    sg[2] = 50;
    guess[3] = NAN;
    report("batch_solve ln_v[3]=nan", rsf_batch_solve_slip_rate(4, fps, sps, lt, tau, sg, et, guess), guess[3]);
    /* the cut-off form: V2 (the state's vc) must be positive, a Kato-Tullis state is refused,
     * and it has no slip-rate solve */
    RsfFrictionParams cut = {RSF_ABI_VERSION, RSF_FORM_CUTOFF, 0.6, 0.01, 1e-3};
    RsfStateParams cs = {RSF_ABI_VERSION, RSF_LAW_AGING, 0.015, 0.01, 0.0};
    report("state_term cutoff vc=0", rsf_state_term(&cut, &cs, 0.0, &out, &d1), out);
    cs.vc = 0.1;
    cs.law = RSF_LAW_KATO_TULLIS;
    report("state_term cutoff kato-tullis", rsf_state_term(&cut, &cs, 0.0, &out, &d1), out);
    cs.law = RSF_LAW_AGING;
    report("solve cutoff", rsf_solve_slip_rate(&cut, 0.0, 30.0, 50.0, 0.0, 0.0, &out, NULL), out);
    report("state_term ln_theta=nan", rsf_state_term(&cut, &cs, NAN, &out, &d1), out);
    fps[1] = cut;
    report("batch_partials cutoff vc[1]=0", rsf_batch_partials(4, fps, sps, lv, lt, f, a, b, r), f[1]);
    sps[1] = cs;
    lv[3] = NAN;
    report("batch_partials ln_v[3]=nan", rsf_batch_partials(4, fps, sps, lv, lt, f, a, b, r), f[3]);
    lv[3] = 0;
    enum RsfStatus ok_cut = rsf_batch_partials(4, fps, sps, lv, lt, f, a, b, r);
    printf("good cutoff batch -> %d\n", (int)ok_cut);
    fps[1] = fp;
    sps[1] = sp;
    /* and a good batch still works */
    guess[3] = 0;
    enum RsfStatus ok = rsf_batch_rates(4, fps, sps, lv, lt, f, a, b, r);
    printf("good batch -> %d\n", (int)ok);
    printf("refused %d accepted %d\n", refused, accepted);
    return 0;
}
