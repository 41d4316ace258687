/* The timing program around CasADi's derivatives (casadi_derivatives.c of one robot, written
 * by derivatives_codegen.py), timed like Pinocchio's derivatives_bench.cpp and our harness
 * (`harness derivatives`): 1000 random states (q in (-pi, pi), v in (-2, 2), a in (-5, 5),
 * tau in (-20, 20)); one warm-up round, then 11 rounds each timing both functions over all
 * states in this thread's CPU time (CLOCK_THREAD_CPUTIME_ID); JSON on stdout with each
 * function's median and minimum mean ns per call over the rounds. Work arrays and outputs
 * are allocated once, before timing.
 *
 *   casadi_derivatives            (NQ defined at compile time) */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "casadi_derivatives.h"

#define STATES 1000
#define ROUNDS 11

typedef int (*fn_t)(const casadi_real **, casadi_real **, casadi_int *, casadi_real *, int);
typedef int (*work_t)(casadi_int *, casadi_int *, casadi_int *, casadi_int *);
typedef const casadi_int *(*sparsity_t)(casadi_int);

struct routine {
    const char *name;
    fn_t f;
    work_t work;
    sparsity_t sparsity;
    int n_out, third; /* third input: 2 a, 3 tau */
};

static const struct routine ROUTINES[] = {
    {"rnea_derivatives", rnea_derivatives, rnea_derivatives_work, rnea_derivatives_sparsity_out, 2, 2},
    {"aba_derivatives", aba_derivatives, aba_derivatives_work, aba_derivatives_sparsity_out, 3, 3},
};

static double now_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e9 * (double)t.tv_sec + (double)t.tv_nsec;
}

static unsigned long long rng = 20261126ULL;
static double uniform(double lo, double hi) { /* xorshift64*, uniform in [lo, hi) */
    rng ^= rng >> 12;
    rng ^= rng << 25;
    rng ^= rng >> 27;
    return lo + (hi - lo) * (double)((rng * 0x2545F4914F6CDD1DULL) >> 11) / 9007199254740992.0;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

volatile double sink;

int main(void) {
    static double x[STATES][4][NQ];
    for (int s = 0; s < STATES; s++) {
        for (int i = 0; i < NQ; i++) x[s][0][i] = uniform(-3.141592653589793, 3.141592653589793);
        for (int i = 0; i < NQ; i++) x[s][1][i] = uniform(-2, 2);
        for (int i = 0; i < NQ; i++) x[s][2][i] = uniform(-5, 5);
        for (int i = 0; i < NQ; i++) x[s][3][i] = uniform(-20, 20);
    }
    const int nr = sizeof ROUTINES / sizeof ROUTINES[0];
    casadi_int *iw[2];
    casadi_real *w[2], *res[2][3];
    for (int r = 0; r < nr; r++) {
        casadi_int sz_arg, sz_res, sz_iw, sz_w;
        ROUTINES[r].work(&sz_arg, &sz_res, &sz_iw, &sz_w);
        iw[r] = malloc(sizeof(casadi_int) * (sz_iw + 1));
        w[r] = malloc(sizeof(casadi_real) * (sz_w + 1));
        for (int k = 0; k < ROUTINES[r].n_out; k++) {
            const casadi_int *sp = ROUTINES[r].sparsity(k);
            res[r][k] = calloc(sp[2 + sp[1]] + 1, sizeof(casadi_real));
        }
    }
    double times[2][ROUNDS];
    for (int round = -1; round < ROUNDS; round++) {
        for (int r = 0; r < nr; r++) {
            const casadi_real *arg[3];
            double t0 = now_ns();
            for (int s = 0; s < STATES; s++) {
                arg[0] = x[s][0];
                arg[1] = x[s][1];
                arg[2] = x[s][ROUTINES[r].third];
                ROUTINES[r].f(arg, res[r], iw[r], w[r], 0);
                sink = res[r][0][0];
            }
            double t = (now_ns() - t0) / STATES;
            if (round >= 0) times[r][round] = t;
        }
    }
    printf("{");
    for (int r = 0; r < nr; r++) {
        qsort(times[r], ROUNDS, sizeof(double), cmp);
        printf("%s\"%s\": {\"median_ns\": %.1f, \"min_ns\": %.1f}", r ? ", " : "", ROUTINES[r].name,
               times[r][ROUNDS / 2], times[r][0]);
    }
    printf("}\n");
    return 0;
}
