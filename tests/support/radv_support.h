#pragma once
// Tests that need RADV's null device skip (with the reason) only where no radeon ICD is installed.
#include <gtest/gtest.h>

#include "gpu/families.h"

#define REQUIRE_RADV()                                                            \
  do {                                                                            \
    try {                                                                         \
      aovar::gpu::find_radeon_icd();                                              \
    } catch (const std::exception& e) {                                           \
      GTEST_SKIP() << "RADV not installed: " << e.what();                         \
    }                                                                             \
  } while (0)
