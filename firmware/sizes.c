// SPDX-License-Identifier: MIT
// For scripts/footprint: one array per public struct, sized sizeof(T), so
// that the cross target's nm reports each struct's size without running
// anything on the target.
#include "gaussfilt/gaussfilt.h"

#define GF_FW_SIZEOF(T) char gf_sizeof_##T[sizeof(T)]
GF_FW_SIZEOF(gf_vec2);
GF_FW_SIZEOF(gf_vec3);
GF_FW_SIZEOF(gf_mat2);
GF_FW_SIZEOF(gf_mat3);
GF_FW_SIZEOF(gf_ellipse);
GF_FW_SIZEOF(gf_innovation);
GF_FW_SIZEOF(gf_kf2);
GF_FW_SIZEOF(gf_kf2_model);
GF_FW_SIZEOF(gf_kf2_meas);
GF_FW_SIZEOF(gf_ekf3);
GF_FW_SIZEOF(gf_ekf3_motion);
GF_FW_SIZEOF(gf_ekf3_meas);
GF_FW_SIZEOF(gf_if2);
GF_FW_SIZEOF(gf_ukf3);
GF_FW_SIZEOF(gf_ukf3_params);
GF_FW_SIZEOF(gf_rng);
GF_FW_SIZEOF(gf_pf3);
GF_FW_SIZEOF(gf_pf3_particle);
