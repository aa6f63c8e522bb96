#pragma once
// What `aovar select` chose (decide/select.h), asserted in one line by the tests of select, its ties and cycles,
// and the GPU estimate.
#include <string>

#include <gtest/gtest.h>

#include "decide/select.h"

namespace aovar::test {

// Success when select answered (ok) and chose `variant`; the failure shows select's text, its reasons.
inline ::testing::AssertionResult chose(const decide::Selection& s, const std::string& variant) {
  if (!s.ok || !s.choice) return ::testing::AssertionFailure() << "nothing chosen, not " << variant << ":\n" << s.text;
  if (s.choice->variant != variant)
    return ::testing::AssertionFailure() << "chose " << s.choice->variant << ", not " << variant << ":\n" << s.text;
  return ::testing::AssertionSuccess();
}

}  // namespace aovar::test
