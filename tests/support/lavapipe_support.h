#pragma once
// Tests that need the Vulkan CPU device (lavapipe) outside aovar's own backend (a program built against the generated
// library) skip, with the reason, only where the Vulkan backend's availability check fails.
#include <string>

#include <gtest/gtest.h>

#include "render/backend.h"

#define REQUIRE_LAVAPIPE()                                                                                   \
  do {                                                                                                       \
    const std::string why =                                                                                  \
        aovar::render::backend_info(aovar::render::backend_for(aovar::variants::Target::vulkan)).unavailable(); \
    if (!why.empty()) GTEST_SKIP() << "no Vulkan CPU device: " << why;                                       \
  } while (0)
