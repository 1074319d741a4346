// SPDX-License-Identifier: MIT
// udu.h's steps for n = 4 (steps.h), in a source of their own: their O(n)
// locals sized for 4 states, where steps.c's stay sized for 3.
#include "steps.h"

#define GF_UDU_NMAX 4u
#include "udu.h"

GF_UDU_STEPS(4)
