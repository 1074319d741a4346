// SPDX-License-Identifier: MIT
// gaussfilt: allocation-free Gaussian filters in C99. Include this, or the
// one module header you need.
#ifndef GAUSSFILT_GAUSSFILT_H
#define GAUSSFILT_GAUSSFILT_H

#include "gaussfilt/config.h"
#include "gaussfilt/status.h"
#include "gaussfilt/mat.h"
#include "gaussfilt/cov2.h"
#include "gaussfilt/kf2.h"
#include "gaussfilt/ekf3.h"
#include "gaussfilt/kf.h"
#include "gaussfilt/ekf.h"
#include "gaussfilt/rng.h"
#include "gaussfilt/if2.h"
#include "gaussfilt/ukf3.h"
#include "gaussfilt/pf3.h"

#define GF_VERSION_MAJOR 0
#define GF_VERSION_MINOR 1
#define GF_VERSION_PATCH 0

#endif
