// bench/compile's floor: the bare glslang front end, in-process, on exactly the sources `aovar generate`
// compiles (expanded by shadergen, not read from disk), on the same thread pool (util::run_parallel) with
// the same number of threads. Per program and target it does only what any in-process glslang user must:
//   vulkan: parse + link + SPIR-V (Vulkan 1.2 rules, SPIR-V 1.5)
//   gl45:   parse + link + SPIR-V (OpenGL client, SPIR-V 1.0): one front-end pass
//   gles30: parse + link (GLSL ES has no SPIR-V)
// with glslang's settings as src/compile/glslang_compiler.cpp sets them. No validation, no reflection, no
// preprocessed text, no hashing, no I/O. `--what product` times compile::compile_program instead (what aovar
// asks of glslang and SPIRV-Tools per program: gl45 also parsed as OpenGL GLSL, gles30 also preprocessed,
// reflection, spirv-val), so the gap between the floor and a cold generate splits into those extra
// checks and everything else.
//
// Usage: aovar_compile_floor_bench MANIFEST TARGETS JOBS [--what bare|product] [--runs N]
// Prints one line per run: "<what> programs=<n> threads=<t> wall=<s> cpu=<s>".
#include <sys/resource.h>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <atomic>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "compile/generate.h"
#include "util/clock.h"
#include "util/parallel.h"

using namespace aovar;
using variants::StageKind;
using variants::Target;

namespace {

double cpu_seconds() {  // user + system of every thread of this process
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

// One parse + link (+ SPIR-V for the SPIR-V targets) with aovar's glslang settings; true when it compiled.
bool bare_compile(const std::string& source, StageKind stage, Target target) {
  EShLanguage lang = stage == StageKind::vertex ? EShLangVertex : EShLangFragment;
  const auto cascading = static_cast<int>(EShMsgCascadingErrors);
  glslang::TShader shader(lang);
  const char* text = source.c_str();
  int length = static_cast<int>(source.size());
  shader.setStringsWithLengths(&text, &length, 1);
  EShMessages messages = static_cast<EShMessages>(cascading);
  if (target == Target::vulkan) {
    shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules | cascading);
  } else if (target == Target::gl45) {
    shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientOpenGL, 100);
    shader.setEnvClient(glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
    messages = static_cast<EShMessages>(EShMsgSpvRules | cascading);
  } else {
    shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientNone, 0);
  }
  if (!shader.parse(GetDefaultResources(), 100, false, messages)) return false;
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages)) return false;
  if (target == Target::gles30) return true;
  glslang::SpvOptions options;
  options.generateDebugInfo = false;
  options.disableOptimizer = true;
  options.validate = false;
  std::vector<unsigned> spirv;
  spv::SpvBuildLogger logger;
  glslang::GlslangToSpv(*program.getIntermediate(lang), spirv, &logger, &options);
  return !spirv.empty();
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 4) {
      std::cerr << "usage: aovar_compile_floor_bench MANIFEST TARGETS JOBS [--what bare|product] [--runs N] "
                   "[--variants GLOB]...\n";
      return 2;
    }
    compile::CompileOptions options;
    for (std::size_t start = 0; start <= std::string(argv[2]).size();) {
      std::string list = argv[2];
      std::size_t end = list.find(',', start);
      auto t = variants::parse_target(list.substr(start, end == std::string::npos ? end : end - start));
      if (!t) throw std::runtime_error(fmt::format("unknown target in '{}'", list));
      options.scope.targets.push_back(*t);
      if (end == std::string::npos) break;
      start = end + 1;
    }
    options.scope.jobs = std::stoi(argv[3]);
    std::string what = "bare";
    int runs = 1;
    for (int i = 4; i + 1 < argc; i += 2) {
      std::string k = argv[i], v = argv[i + 1];
      if (k == "--what" && (v == "bare" || v == "product")) what = v;
      else if (k == "--runs") runs = std::stoi(v);
      else if (k == "--variants") options.globs.push_back(v);  // as generate's (bench/compile's smoke mode)
      else throw std::runtime_error("unknown option " + k + " " + v);
    }

    // The same programs as generate: plan_space expands them (outside the timed part).
    options.scope.manifest = argv[1];
    compile::CompiledSpace planned = compile::plan_space(options);
    const auto& programs = planned.space.programs;
    std::size_t count = planned.targets.size() * programs.size();
    compile::initialise_compiler();  // glslang's process set-up: once, as in generate
    for (int run = 0; run < runs; ++run) {
      std::atomic<int> failed{0};
      compile::ValidationMemo validated;  // per run, as generate has one per run
      double cpu0 = cpu_seconds();
      auto start = util::Clock::now();
      util::run_parallel(count, options.scope.jobs, [&](std::size_t i) {
        std::size_t t = i / programs.size(), p = i % programs.size();
        const std::string& source = planned.builds[t][p].source;
        bool ok = what == "bare" ? bare_compile(source, programs[p].stage, planned.targets[t])
                                 : compile::compile_program(source, programs[p].stage, planned.targets[t], &validated).ok;
        if (!ok) ++failed;
      });
      double wall = util::seconds_since(start), cpu = cpu_seconds() - cpu0;
      if (failed) throw std::runtime_error(fmt::format("{} of {} programs failed to compile", failed.load(), count));
      std::cout << fmt::format("{} programs={} threads={} wall={:.3f} cpu={:.2f}\n", what, count,
                               std::min<std::size_t>(util::pool_threads(options.scope.jobs), count), wall, cpu);
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "aovar_compile_floor_bench: " << e.what() << "\n";
    return 2;
  }
}
