#pragma once
// A stress run for people: the case catalogue (--list-cases), and each failed variant with its failing
// checks and their reproducers, then the counts. What `aovar stress` prints.
#include <string>
#include <vector>

#include "stress/stress.h"

namespace aovar::stress {

std::string cases_text(const std::vector<Case>& cases);  // name, scene and what each case tests
std::string to_text(const Result& result, const Options& options, const std::vector<Case>& cases);

}  // namespace aovar::stress
