// SPDX-License-Identifier: MIT
// The book's exercises (docs/exercises.md), every number in one place:
// Probabilistic Robotics, chapter 3, exercises 1, 2 and 4, as the in-process
// program (examples/exercises.c), the simulator (gf_sim --exercise), the node's
// presets (sim/node_model.c: book-car, book-robot) and the checker (gf_check)
// use them. Header-only, C99, no library needed.
//
// Four of them are parameters a student can change on the command line of
// every one of those programs (and of scripts/demo); the tables that then
// differ from the book's printed ones are named with the option that made
// them differ (gf_book_differs):
//
//   --meas-var V     exercise 2's measurement variance Q (the book: 10)
//   --z Z            exercise 2's measurement (the book: z = 5)
//   --steps N        exercise 2's predictions before it (the book: 5)
//   --heading-var V  exercise 4's initial heading variance (the book: 10000)
#ifndef GF_BOOK_H
#define GF_BOOK_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Exercises 1 and 2: the car, x = (position, velocity), one step per second,
// pushed by a random acceleration of variance 1: R = G G^T, G = (0.5, 1)^T.
#define GF_BOOK_CAR_DT 1.0
#define GF_BOOK_CAR_ACCEL_VAR 1.0
// Exercise 1: predictions only (Table 1.1 prints t = 0..5, Figure 1.2
// the correlation up to t = 10).
#define GF_BOOK_EX1_STEPS 10
// Exercise 2: after 5 predictions, the position is measured as z = 5 with
// variance Q = 10 (Table 2.1).
#define GF_BOOK_EX2_STEPS 5
#define GF_BOOK_EX2_Z 5.0
#define GF_BOOK_EX2_Q 10.0
// Exercise 4: the robot at the origin, known to 0.01 in x and y, heading
// unknown (variance 10000); it moves 1 forward (u = (1, 0), no motion
// noise), then sees x = -0.7 with variance 0.01 (Tables 4.1, 4.2).
#define GF_BOOK_EX4_XY_VAR 0.01
#define GF_BOOK_EX4_HEADING_VAR 10000.0
#define GF_BOOK_EX4_D 1.0
#define GF_BOOK_EX4_PHI 0.0
#define GF_BOOK_EX4_Z (-0.7)
#define GF_BOOK_EX4_Q 0.01

// The parameters a student may change (see the top).
typedef struct gf_book {
    double ex2_q;
    double ex2_z;
    int ex2_steps;
    double ex4_heading_var;
} gf_book;

#define GF_BOOK_DEFAULTS                                                       \
    {                                                                          \
        GF_BOOK_EX2_Q, GF_BOOK_EX2_Z, GF_BOOK_EX2_STEPS,                       \
            GF_BOOK_EX4_HEADING_VAR                                            \
    }

// The usage line of the options.
#define GF_BOOK_USAGE "[--meas-var V] [--z Z] [--steps N] [--heading-var V]"

// a != b, without comparing doubles for equality (-Wfloat-equal).
static inline int gf_book_changed(double a, double b)
{
    return a < b || a > b;
}

// Takes argv[*i] (and its value) if it is one of the options: returns 1
// and moves *i past it, 0 if it is not one, -1 on a bad value (a message
// on stderr).
static inline int gf_book_option(gf_book *b, int argc, char **argv, int *i)
{
    const char *o = argv[*i], *v = *i + 1 < argc ? argv[*i + 1] : NULL;
    char *end = NULL;
    double x;
    if (strcmp(o, "--meas-var") != 0 && strcmp(o, "--z") != 0 &&
        strcmp(o, "--steps") != 0 && strcmp(o, "--heading-var") != 0) {
        return 0;
    }
    if (v == NULL) {
        fprintf(stderr, "%s needs a value\n", o);
        return -1;
    }
    x = strtod(v, &end);
    if (end == v || *end != '\0' || !(x >= -1e300 && x <= 1e300)) {
        fprintf(stderr, "%s %s: not a number\n", o, v);
        return -1;
    }
    if (strcmp(o, "--steps") == 0) {
        if (x < 1 || x > 1000 || gf_book_changed(x, (double)(int)x)) {
            fprintf(stderr, "--steps %s: a whole number 1..1000\n", v);
            return -1;
        }
        b->ex2_steps = (int)x;
    } else if (strcmp(o, "--z") == 0) {
        b->ex2_z = x;
    } else if (!(x > 0.0)) {
        fprintf(stderr, "%s %s: a variance > 0\n", o, v);
        return -1;
    } else if (strcmp(o, "--meas-var") == 0) {
        b->ex2_q = x;
    } else {
        b->ex4_heading_var = x;
    }
    *i += 2;
    return 1;
}

// Writes which options make table ("1.1", "2.1", "4.2") differ from the
// book's, e.g. "--meas-var 4 (the book: 10)", into out; returns 1 if any.
static inline int gf_book_differs(const gf_book *b, const char *table,
                                  char *out, size_t size)
{
    size_t n = 0;
    out[0] = '\0';
#define GF_BOOK_ADD(...)                                                       \
    do {                                                                       \
        if (n < size)                                                          \
            n += (size_t)snprintf(out + n, size - n, __VA_ARGS__);             \
    } while (0)
    if (strcmp(table, "2.1") == 0) {
        if (gf_book_changed(b->ex2_q, GF_BOOK_EX2_Q)) {
            GF_BOOK_ADD("%s--meas-var %g (the book: %g)", n ? ", " : "",
                        b->ex2_q, GF_BOOK_EX2_Q);
        }
        if (gf_book_changed(b->ex2_z, GF_BOOK_EX2_Z)) {
            GF_BOOK_ADD("%s--z %g (the book: %g)", n ? ", " : "", b->ex2_z,
                        GF_BOOK_EX2_Z);
        }
        if (b->ex2_steps != GF_BOOK_EX2_STEPS) {
            GF_BOOK_ADD("%s--steps %d (the book: %d)", n ? ", " : "",
                        b->ex2_steps, GF_BOOK_EX2_STEPS);
        }
    } else if (strcmp(table, "4.2") == 0) {
        if (gf_book_changed(b->ex4_heading_var, GF_BOOK_EX4_HEADING_VAR)) {
            GF_BOOK_ADD("--heading-var %g (the book: %g)", b->ex4_heading_var,
                        GF_BOOK_EX4_HEADING_VAR);
        }
    }
#undef GF_BOOK_ADD
    return n > 0;
}

#endif
