/* The timing and checking program around CasADi's generated C (casadi.c of one robot), built
 * by casadi_bench.py, timed like our side (benches/baselines/casadi/ours.rs):
 *
 *   casadi_bench check STATES S         every routine at each of the S states, printed
 *   casadi_bench time ROUTINE STATES S BATCHES CALLS   ns of thread CPU per call, per batch
 *
 * STATES: S states of 4 n doubles (q, v, a, tau in CasADi's joint order), native byte
 * order. Outputs are written dense, row-major (CasADi omits a matrix's structural zeros:
 * its sparsity pattern puts them back). The work arrays are allocated once, before timing. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "casadi.h"

typedef int (*fn_t)(const casadi_real **, casadi_real **, casadi_int *, casadi_real *, int);
typedef int (*work_t)(casadi_int *, casadi_int *, casadi_int *, casadi_int *);
typedef const casadi_int *(*sparsity_t)(casadi_int);

/* Inputs by index into a state: 0 q, 1 v, 2 a, 3 tau. */
struct routine {
    const char *name;
    fn_t f;
    work_t work;
    sparsity_t sparsity;
    int n_in, n_out, in[3];
};

static const struct routine ROUTINES[] = {
    {"crba", crba, crba_work, crba_sparsity_out, 1, 1, {0}},
    {"bias", bias, bias_work, bias_sparsity_out, 2, 1, {0, 1}},
    {"mass_bias", mass_bias, mass_bias_work, mass_bias_sparsity_out, 2, 2, {0, 1}},
    {"rnea", rnea, rnea_work, rnea_sparsity_out, 3, 1, {0, 1, 2}},
    {"aba", aba, aba_work, aba_sparsity_out, 3, 1, {0, 1, 3}},
};
#define N_ROUTINES (sizeof ROUTINES / sizeof ROUTINES[0])

static double now_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e9 * (double)t.tv_sec + (double)t.tv_nsec;
}

static double *read_states(const char *path, long count) {
    double *x = malloc(sizeof(double) * 4 * NQ * count);
    FILE *f = fopen(path, "rb");
    if (!f || fread(x, sizeof(double), 4 * NQ * count, f) != (size_t)(4 * NQ * count)) {
        fprintf(stderr, "cannot read %ld states from %s\n", count, path);
        exit(1);
    }
    fclose(f);
    return x;
}

/* Buffers of one routine: work arrays and one output buffer per output (nnz entries). */
struct call {
    const struct routine *r;
    const casadi_real *arg[8];
    casadi_real *res[8];
    casadi_int *iw;
    casadi_real *w;
};

static struct call prepare(const struct routine *r) {
    struct call c = {r};
    casadi_int sz_arg, sz_res, sz_iw, sz_w;
    r->work(&sz_arg, &sz_res, &sz_iw, &sz_w);
    c.iw = malloc(sizeof(casadi_int) * (sz_iw + 1));
    c.w = malloc(sizeof(casadi_real) * (sz_w + 1));
    for (int k = 0; k < r->n_out; k++) {
        const casadi_int *sp = r->sparsity(k);
        c.res[k] = calloc(sp[2 + sp[1]] + 1, sizeof(casadi_real));
    }
    return c;
}

static void point(struct call *c, const double *state) {
    for (int k = 0; k < c->r->n_in; k++) c->arg[k] = state + c->r->in[k] * NQ;
}

/* Output k of the last call, dense and row-major. */
static void print_dense(const struct call *c, int k) {
    const casadi_int *sp = c->r->sparsity(k);
    casadi_int rows = sp[0], cols = sp[1];
    const casadi_int *colind = sp + 2, *row = sp + 3 + cols;
    double *dense = calloc(rows * cols, sizeof(double));
    for (casadi_int j = 0; j < cols; j++)
        for (casadi_int e = colind[j]; e < colind[j + 1]; e++) dense[row[e] * cols + j] = c->res[k][e];
    for (casadi_int i = 0; i < rows * cols; i++) printf(" %.17g", dense[i]);
    free(dense);
}

int main(int argc, char **argv) {
    if (argc >= 4 && strcmp(argv[1], "check") == 0) {
        long count = atol(argv[3]);
        double *x = read_states(argv[2], count);
        for (size_t r = 0; r < N_ROUTINES; r++) {
            struct call c = prepare(&ROUTINES[r]);
            for (long s = 0; s < count; s++) {
                point(&c, x + 4 * NQ * s);
                c.r->f(c.arg, c.res, c.iw, c.w, 0);
                printf("%s %ld", c.r->name, s);
                for (int k = 0; k < c.r->n_out; k++) print_dense(&c, k);
                printf("\n");
            }
        }
        return 0;
    }
    if (argc >= 7 && strcmp(argv[1], "time") == 0) {
        const struct routine *r = NULL;
        for (size_t k = 0; k < N_ROUTINES; k++)
            if (strcmp(ROUTINES[k].name, argv[2]) == 0) r = &ROUTINES[k];
        if (!r) {
            fprintf(stderr, "no routine %s\n", argv[2]);
            return 2;
        }
        long count = atol(argv[4]), batches = atol(argv[5]), calls = atol(argv[6]);
        double *x = read_states(argv[3], count);
        struct call c = prepare(r);
        volatile double sink = 0;
        for (long b = -1; b < batches; b++) { /* batch -1: warm-up */
            double t0 = now_ns();
            for (long i = 0; i < calls; i++) {
                point(&c, x + 4 * NQ * (i % count));
                r->f(c.arg, c.res, c.iw, c.w, 0);
                sink += c.res[0][0];
            }
            double t1 = now_ns();
            if (b >= 0) printf("%.2f\n", (t1 - t0) / (double)calls);
        }
        return 0;
    }
    fprintf(stderr, "usage: %s check STATES S | time ROUTINE STATES S BATCHES CALLS\n", argv[0]);
    return 2;
}
