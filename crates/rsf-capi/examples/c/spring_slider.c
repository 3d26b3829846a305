/* A host code in C calling rsf through its C ABI: the BP1-like spring-slider of
 * ../shared/notes/fault-sim.md (regularized friction, aging law, radiation damping,
 * k = kc/2), integrated by the host's own fixed-step RK4 in (ln V, ln theta, tau) with the slip
 * rate from rsf_solve_slip_rate at every stage -- formulation C of the fault codes.
 * Prints the first event onset (V >= 1e-3 m/s) in years, the peak slip rate and the
 * recurrence interval; checks the error reporting. Build (the test does this):
 *   gcc spring_slider.c -I../../include ../../../../target/release/librsf_capi.a -lm -lpthread -ldl
 */
#include <math.h>
#include <stdio.h>
#include "rsf.h"

static const double YEAR = 3.1536e7;

typedef struct {
  RsfFrictionParams fp;
  RsfStateParams sp;
  double sigma, eta, k, vp;
} Slider;

/* y = (tau_el, ln_theta); the slip rate solves tau_el - eta V = sigma f(V, theta) */
static int rates(const Slider *s, const double *y, double *ln_v, double *dy) {
  double psi, rate;
  if (rsf_psi(&s->sp, s->fp.v0, y[1], &psi) != RSF_OK) return 1;
  if (rsf_solve_slip_rate(&s->fp, psi, y[0], s->sigma, s->eta, *ln_v, ln_v, NULL) != RSF_OK) return 1;
  if (rsf_ln_theta_rate(&s->sp, *ln_v, y[1], &rate) != RSF_OK) return 1;
  dy[0] = s->k * (s->vp - exp(*ln_v)); /* loading by the plate through the spring */
  dy[1] = rate;
  return 0;
}

int main(void) {
  if (rsf_abi_version() != RSF_ABI_VERSION) { printf("ABI mismatch\n"); return 1; }
  Slider s;
  s.fp = (RsfFrictionParams){RSF_ABI_VERSION, RSF_FORM_REGULARIZED, 0.6, 0.010, 1e-6};
  s.sp = (RsfStateParams){RSF_ABI_VERSION, RSF_LAW_AGING, 0.015, 0.008, 0.0};
  s.sigma = 50e6;
  s.eta = 2670.0 * 3464.0 / 2.0;
  s.k = 0.5 * s.sigma * (0.015 - 0.010) / 0.008; /* kc / 2 */
  s.vp = 1e-9;
  /* start at V = 0.9 Vp, theta = Dc/Vp: tau from the friction at that state */
  double y[2], ln_v = log(0.9e-9), f, fx, fpsi, psi;
  y[1] = log(0.008 / 1e-9);
  rsf_psi(&s.sp, s.fp.v0, y[1], &psi);
  rsf_friction(&s.fp, ln_v, psi, &f, &fx, &fpsi);
  y[0] = s.sigma * f + s.eta * 0.9e-9;
  double t = 0.0, onsets[3] = {0, 0, 0}, vmax = 0.0;
  int n_on = 0, seismic = 0;
  while (t < 60.0 * YEAR && n_on < 3) {
    /* step: small where V is large (a slip of 1e-5 m per step), at most 0.005 yr */
    double v = exp(ln_v), h = fmin(0.005 * YEAR, 1e-5 / v);
    double k1[2], k2[2], k3[2], k4[2], yt[2], lv = ln_v;
    if (rates(&s, y, &lv, k1)) break;
    for (int i = 0; i < 2; i++) yt[i] = y[i] + 0.5 * h * k1[i];
    if (rates(&s, yt, &lv, k2)) break;
    for (int i = 0; i < 2; i++) yt[i] = y[i] + 0.5 * h * k2[i];
    if (rates(&s, yt, &lv, k3)) break;
    for (int i = 0; i < 2; i++) yt[i] = y[i] + h * k3[i];
    if (rates(&s, yt, &lv, k4)) break;
    for (int i = 0; i < 2; i++) y[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    t += h;
    double dy[2];
    if (rates(&s, y, &ln_v, dy)) break;
    v = exp(ln_v);
    if (v > vmax) vmax = v;
    if (!seismic && v >= 1e-3) { onsets[n_on++] = t; seismic = 1; }
    if (seismic && v < 1e-3) seismic = 0;
  }
  printf("onset %.4f yr\ninterval %.4f yr\npeak %.4f m/s\n", onsets[0] / YEAR, (onsets[2] - onsets[1]) / YEAR, vmax);
  /* errors are codes with a message, never a crash */
  RsfStateParams bad = s.sp;
  bad.law = 42;
  double r;
  RsfStatus st = rsf_ln_theta_rate(&bad, 0.0, 0.0, &r);
  printf("unknown law -> %d: %s\n", (int)st, rsf_last_error());
  st = rsf_solve_slip_rate(&s.fp, 0.0, -1.0, s.sigma, s.eta, 0.0, &r, NULL);
  printf("negative stress -> %d: %s\n", (int)st, rsf_last_error());
  return 0;
}
