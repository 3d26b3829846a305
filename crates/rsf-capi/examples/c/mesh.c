/* A host that integrates V and theta (as QDYN does) with a mesh: the parameters of a fault of
 * 64 elements, checked once by rsf_mesh_new, then the partials and the state rate at every
 * right-hand side, written beside the host's own closed forms (classic friction, aging law):
 * dmu/dV = a/V, dmu/dtheta = b/theta, dtheta/dt = 1 - V theta/Dc. Then a trial stage at V < 0
 * under each domain policy. Prints `name: value` lines and `mesh: ok` when every check held;
 * exits 1 otherwise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "rsf.h"

#define N 64

static int failures = 0;

static void expect(int ok, const char *what) {
    if (!ok) {
        failures++;
        printf("FAILED: %s\n", what);
    }
}

static double rel(double x, double y) { return fabs(x - y) / fmax(fabs(x), fabs(y)); }

int main(void) {
    RsfFrictionParams fp[N];
    RsfStateParams sp[N];
    double a[N], b[N], dc[N], v[N], theta[N], dv[N], dth[N], rate[N], mu[N];
    for (int i = 0; i < N; i++) {
        a[i] = 0.010 + 0.004 * i / (N - 1.0);  /* a and b vary along the fault */
        b[i] = 0.015 - 0.006 * i / (N - 1.0);
        dc[i] = 8e-3;
        fp[i] = (RsfFrictionParams){RSF_ABI_VERSION, RSF_FORM_CLASSIC, 0.6, a[i], 1e-9};
        sp[i] = (RsfStateParams){RSF_ABI_VERSION, RSF_LAW_AGING, b[i], dc[i], 0.0};
        v[i] = 1e-9 * pow(10.0, 10.0 * i / (N - 1.0));  /* 1e-9 to 10 m/s */
        theta[i] = 0.3 * dc[i] / v[i];
    }
    RsfMesh *mesh = NULL;
    if (rsf_mesh_new(N, fp, sp, RSF_DOMAIN_REFUSE, &mesh) != RSF_OK) {
        printf("rsf_mesh_new: %s\n", rsf_last_error());
        return 1;
    }
    expect(rsf_mesh_partials(mesh, N, v, theta, dv, dth) == RSF_OK, "partials");
    expect(rsf_mesh_state_rate(mesh, N, v, theta, rate) == RSF_OK, "state rate");
    expect(rsf_mesh_friction(mesh, N, v, theta, mu) == RSF_OK, "friction");
    double worst = 0;
    for (int i = 0; i < N; i++) {
        worst = fmax(worst, rel(dv[i], a[i] / v[i]));
        worst = fmax(worst, rel(dth[i], b[i] / theta[i]));
        worst = fmax(worst, rel(rate[i], 1.0 - v[i] * theta[i] / dc[i]));
        worst = fmax(worst, rel(mu[i], 0.6 + a[i] * log(v[i] / 1e-9) + b[i] * log(1e-9 * theta[i] / dc[i])));
    }
    printf("largest relative difference from the host's closed forms: %.3e\n", worst);
    expect(worst < 1e-13, "closed forms");

    /* a trial stage that overshoots to V < 0 at one element */
    v[5] = -2.58e-10;
    enum RsfStatus st = rsf_mesh_partials(mesh, N, v, theta, dv, dth);
    printf("refuse at V < 0: %d: %s\n", (int)st, rsf_last_error());
    expect(st == RSF_BAD_INPUT, "refused at V < 0");
    rsf_mesh_free(mesh);

    mesh = NULL;
    expect(rsf_mesh_new(N, fp, sp, RSF_DOMAIN_CONTINUE, &mesh) == RSF_OK, "continue mesh");
    expect(rsf_mesh_partials(mesh, N, v, theta, dv, dth) == RSF_OK, "partials continued");
    expect(rsf_mesh_state_rate(mesh, N, v, theta, rate) == RSF_OK, "rate continued");
    printf("continued at V = %g: dmu/dV = %.6e (a/V = %.6e), dtheta/dt = %.6e\n", v[5], dv[5], a[5] / v[5],
           rate[5]);
    expect(dv[5] == a[5] / v[5] && rate[5] == 1.0 - v[5] * theta[5] / dc[5], "closed forms at V < 0");
    rsf_mesh_free(mesh);

    if (failures) return 1;
    printf("mesh: ok\n");
    return 0;
}
