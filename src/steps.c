// SPDX-License-Identifier: MIT
#include "steps.h"

#include "udu.h"

GF_UDU_STEPS(2)
GF_UDU_STEPS(3)
