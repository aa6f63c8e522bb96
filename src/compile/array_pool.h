#pragma once
// Constant arrays of the C++ embedding that variants share: an array is written once per distinct initializer and
// every variant with that initializer refers to it by name, so the generated source grows with the distinct
// parameter sets and plans, not with the variants (kVariantParams_<n>, the plan's kDraws_<n>, ...).
#include <map>
#include <string>

#include <fmt/format.h>

namespace aovar::compile {

class ArrayPool {
 public:
  explicit ArrayPool(std::string& out) : out_(out) {}

  // The name of the array `const <type> <prefix>_<n>[] = {<init> };`, written to the output the first time this
  // type and initializer come. `init` is the element list, each element ending in a comma.
  const std::string& add(const std::string& type, const std::string& prefix, const std::string& init) {
    int& count = counts_[prefix];
    auto [it, added] = names_.emplace(type + '\n' + prefix + '\n' + init, fmt::format("{}_{}", prefix, count));
    if (added) {
      ++count;
      out_ += fmt::format("const {} {}[] = {{{} }};\n", type, it->second, init);
    }
    return it->second;
  }

 private:
  std::string& out_;
  std::map<std::string, std::string> names_;  // type, prefix and initializer -> the array's name
  std::map<std::string, int> counts_;         // arrays written per prefix
};

}  // namespace aovar::compile
