/* Issue 38 item 9: a recorded path of any length in C. 2,000 poses on three quarters of a
 * circle of radius 2 m, from (2, 0) to (0, -2), built by `_init_waypoints_in` in storage
 * the caller allocates (`_waypoints_words(n)` numbers), in double and float: the reference
 * ends at (0, -2) and stays on the circle; `_init_waypoints` (the reference's own storage,
 * the firmware's capacity) refuses 2,000 points and says what to do; storage too short is
 * refused naming `words`. Built and run by tests/c_programs.rs; prints "ok" at the end. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wmr.h"

#define N 2000

#define LONG_PATH(P, T, TOL)                                                                    \
    static int long_path_##P(void) {                                                            \
        static T pts[N][2];                                                                     \
        wmr_error err;                                                                          \
        wmr_reference_##P r;                                                                    \
        wmr_reference_state_##P s;                                                              \
        size_t words = wmr_reference_##P##_waypoints_words(N);                                  \
        T *storage;                                                                             \
        int i;                                                                                  \
        double worst = 0;                                                                       \
        for (i = 0; i < N; i++) {                                                               \
            double a = i * 1.5 * 3.14159265358979323846 / (N - 1);                              \
            pts[i][0] = (T)(2.0 * cos(a));                                                      \
            pts[i][1] = (T)(2.0 * sin(a));                                                      \
        }                                                                                       \
        if (words != 37 * (size_t)N - 28) {                                                     \
            printf("FAIL " #P ": words %zu\n", words);                                          \
            return 1;                                                                           \
        }                                                                                       \
        if (wmr_reference_##P##_init_waypoints(&r, (const T(*)[2])pts, N, 0.3f, 0.5f, &err) != WMR_OUT_OF_RANGE \
            || strcmp(err.field, "n") != 0 || !strstr(err.reason, "_init_waypoints_in")) {       \
            printf("FAIL " #P ": 2000 points in the own storage: %s %s\n", err.field, err.reason); \
            return 1;                                                                           \
        }                                                                                       \
        storage = malloc(words * sizeof(T));                                                    \
        if (!storage) return 1;                                                                 \
        if (wmr_reference_##P##_init_waypoints_in(&r, (const T(*)[2])pts, N, 0.3f, 0.5f, storage, words - 1, &err) \
                != WMR_OUT_OF_RANGE                                                             \
            || strcmp(err.field, "words") != 0) {                                               \
            printf("FAIL " #P ": short storage: %s %s\n", err.field, err.reason);               \
            return 1;                                                                           \
        }                                                                                       \
        if (wmr_reference_##P##_init_waypoints_in(&r, (const T(*)[2])pts, N, 0.3f, 0.5f, storage, words, &err) != WMR_OK) { \
            printf("FAIL " #P ": %s %s\n", err.field, err.reason);                              \
            return 1;                                                                           \
        }                                                                                       \
        for (i = 0; i <= 400; i++) {                                                            \
            double e;                                                                           \
            if (wmr_reference_##P##_state_at(&r, (T)(i * 0.1), &s) != WMR_OK) return 1;         \
            e = fabs(hypot(s.pose.x, s.pose.y) - 2.0);                                          \
            if (e > worst) worst = e;                                                           \
        }                                                                                       \
        if (worst > TOL || fabs(s.pose.x) > TOL || fabs(s.pose.y + 2.0) > TOL) {                \
            printf("FAIL " #P ": off the circle by %g, ends at (%g, %g)\n", worst, (double)s.pose.x, \
                   (double)s.pose.y);                                                           \
            return 1;                                                                           \
        }                                                                                       \
        printf("pass " #P ": 2000 points in %zu numbers, on the circle within %.2g m, ends at (%.6f, %.6f)\n", \
               words, worst, (double)s.pose.x, (double)s.pose.y);                               \
        free(storage);                                                                          \
        return 0;                                                                               \
    }

LONG_PATH(f64, double, 1e-6)
LONG_PATH(f32, float, 1e-3)

int main(void) {
    if (long_path_f64() || long_path_f32()) return 1;
    printf("ok\n");
    return 0;
}
