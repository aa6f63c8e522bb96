// CI shader-compile test: compiles, in-process and without the cache, every program that the variants
// of one algorithm need for one target, and names every failing variant.
// Usage: aovar_shader_compile <manifest> <algorithm> <target>
#include <fmt/format.h>

#include <iostream>

#include "compile/generate.h"

int main(int argc, char** argv) {
  using namespace aovar;
  if (argc != 4) {
    std::cerr << "usage: aovar_shader_compile <manifest> <algorithm> <vulkan|gl45|gles30>\n";
    return 2;
  }
  auto target = variants::parse_target(argv[3]);
  if (!target) {
    std::cerr << "unknown target " << argv[3] << "\n";
    return 2;
  }
  try {
    compile::CompileOptions options;
    options.scope.targets = {*target};
    options.globs = {std::string(argv[2]) + "-*"};
    options.scope.manifest = argv[1];
    auto c = compile::compile_space(options);
    for (const auto& d : c.diagnostics) std::cout << d << "\n";
    if (c.space.variants.empty()) {
      std::cout << "no variant of algorithm " << argv[2] << " in " << argv[1] << "\n";
      return 1;
    }
    int failing = 0;
    for (std::size_t p = 0; p < c.space.programs.size(); ++p) {
      if (c.builds[0][p].ok) continue;
      for (const auto& key : c.variants_using(static_cast<int>(p))) {
        std::cout << "FAILED variant " << key << " (program " << c.space.programs[p].key << ")\n";
        ++failing;
      }
    }
    const auto& s = c.stats[0];
    std::cout << fmt::format("{} {}: {} programs compiled, {} unique, {} failed; {} variants, {} failing\n", argv[2],
                             argv[3], s.compiled, s.unique, s.failed, c.space.variants.size(), failing);
    return c.ok() && s.compiled == s.programs ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
}
