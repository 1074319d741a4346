// SPDX-License-Identifier: MIT
// udu.h's steps for n = 4 (steps.h), in a source of their own: KF2 and
// EKF3 link steps.c without them.
#include "steps.h"

#include "udu.h"

GF_UDU_STEPS(4)
