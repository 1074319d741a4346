// SPDX-License-Identifier: MIT
// The descriptor of a model gaussfilt.codegen wrote (docs/codegen.md): its
// sizes, names and callbacks, for a program that reads or loads the model.
// Each generated NAME_model.h includes this header; gf_node reads a
// generated library's descriptor through gf_codegen_exported.
#ifndef GAUSSFILT_CODEGEN_H
#define GAUSSFILT_CODEGEN_H

#include "gaussfilt/ekf.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gf_codegen_sensor {
    const char *name;
    unsigned m;
    unsigned angle_mask;           // quantities that are angles
    const char *const *quantities; // m names
    gf_ekf_meas_fn h;
    void (*Q)(const gf_real *params, gf_real *Q); // m x m
} gf_codegen_sensor;

typedef struct gf_codegen_model {
    unsigned version; // 1
    const char *name;
    unsigned n, nu, nparams;
    unsigned angles; // the states that are angles
    const char *const *states, *const *units, *const *inputs, *const *params;
    gf_ekf_motion_fn g;
    void (*R)(const gf_real *params, gf_real dt, gf_real *R); // n x n
    unsigned nsensors;
    const gf_codegen_sensor *sensors;
} gf_codegen_model;

// The descriptor under a fixed name, for a program that loads the model
// from a shared object (gf_node's type = generated): the export's version,
// the size of the gf_real it was built with, and the descriptor. A
// generated model defines gf_codegen_exported when its C is built with
// -DGF_CODEGEN_EXPORT (one model per shared object).
#define GF_CODEGEN_EXPORT_VERSION 1u
typedef struct gf_codegen_export {
    unsigned version;   // GF_CODEGEN_EXPORT_VERSION
    unsigned real_size; // sizeof(gf_real): 4 float, 8 double
    const gf_codegen_model *model;
} gf_codegen_export;

#ifdef __cplusplus
}
#endif

#endif
