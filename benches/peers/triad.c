/* Memory-bandwidth probe for the roofline: a STREAM-style triad a[i] = b[i] + s*c[i].
 *
 *   triad N REPS        (thread count from OMP_NUM_THREADS)
 *
 * Three arrays of N doubles, first touched by the threads that use them. Prints one
 * line, `triad threads=T bytes=B best_gbs=X median_gbs=Y`, counting 24 bytes per
 * element (two reads and one write, STREAM's convention: the write-allocate read of
 * a[] is not counted, so the figure is what a streaming kernel can move). 1 GB = 1e9 B.
 * Build: gcc -O2 -fopenmp -o triad triad.c */
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

static int cmp(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: triad N REPS\n");
        return 2;
    }
    long n = atol(argv[1]);
    int reps = atoi(argv[2]);
    if (n < 1024 || reps < 1) {
        fprintf(stderr, "error: N must be >= 1024 and REPS >= 1\n");
        return 2;
    }
    double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *c = malloc(n * sizeof *c);
    double *t = malloc(reps * sizeof *t);
    if (!a || !b || !c || !t) {
        fprintf(stderr, "error: cannot allocate 3 x %ld doubles\n", n);
        return 1;
    }
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; i++) {
        a[i] = 0.0;
        b[i] = 1.0;
        c[i] = 2.0;
    }
    const double s = 0.5;
    double check = 0.0;
    for (int r = 0; r < reps; r++) {
        double t0 = omp_get_wtime();
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; i++) a[i] = b[i] + s * c[i];
        t[r] = omp_get_wtime() - t0;
        check += a[(r * 7919L) % n]; /* keeps the loop from being optimised away */
    }
    qsort(t, reps, sizeof *t, cmp);
    double bytes = 24.0 * n;
    printf("triad threads=%d bytes=%.0f best_gbs=%.2f median_gbs=%.2f check=%g\n", omp_get_max_threads(),
           3.0 * 8.0 * n, bytes / t[0] / 1e9, bytes / t[reps / 2] / 1e9, check);
    free(a);
    free(b);
    free(c);
    free(t);
    return 0;
}
