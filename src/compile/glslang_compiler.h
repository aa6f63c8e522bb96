#pragma once
// In-process glslang front end + SPIR-V back end + SPIRV-Tools validation for one program and target.
// Thread-safe: call from any number of threads (initialise_compiler() runs glslang's process setup once).
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "variants/manifest.h"

namespace aovar::compile {

struct Diagnostic {
  enum class Severity { error, warning };
  Severity severity = Severity::error;
  int source = -1;  // source-string number from the #line directives (0 = preamble, k = file k), -1 = none
  int line = 0;
  std::string message;
};

struct UniformMember {
  std::string name;  // member name without the block prefix
  bool is_float = false;
};

struct CompileOutput {
  bool ok = false;
  std::vector<std::uint32_t> spirv;      // vulkan: Vulkan SPIR-V 1.5; gl45: GL SPIR-V 1.0; gles30: empty
  std::string identity;                  // equal identity = same program (SPIR-V bytes or preprocessed text)
  std::vector<Diagnostic> diagnostics;
  std::vector<UniformMember> params_block;  // members of block AOParams (all, used or not)
};

void initialise_compiler();

// spirv-val's verdicts ("" = valid, else its messages) by target environment and SPIR-V hash, shared by the
// programs of one run. spirv-val is a pure function of the environment and the words, and many programs
// compile to the same binary (on gl45 most do), so each distinct binary is validated once. Thread-safe.
class ValidationMemo {
 public:
  std::optional<std::string> find(const std::string& key) const;
  void remember(const std::string& key, const std::string& errors);

 private:
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::string> results_;
};

// vulkan: GLSL 450 -> SPIR-V 1.5 (Vulkan 1.2 rules), validated by spirv-val.
// gl45: GLSL 450 core validated as OpenGL GLSL, plus GL SPIR-V (ARB_gl_spirv) validated by spirv-val.
// gles30: GLSL ES 3.00 validated by glslang's ES front end; identity from the preprocessed text.
// `memo` (optional) skips validating a binary already validated in this run.
CompileOutput compile_program(const std::string& source, variants::StageKind stage, variants::Target target,
                              ValidationMemo* memo = nullptr);

// spirv-val's messages for the SPIR-V a program of `target` compiled to ("" when valid, as compile_program
// validated it; gles30 has none): what a compile-cache entry is checked with before it is used.
std::string spirv_errors(const std::vector<std::uint32_t>& spirv, variants::Target target, ValidationMemo* memo = nullptr);

// The GLSL ES source after glslang's preprocessor: macros expanded, #if resolved, comments gone, #line kept.
// What the GL compilers' loop unroller reads (gpu/gl/unroll.h). Throws std::runtime_error with glslang's log.
std::string preprocess_es(const std::string& source, variants::StageKind stage);

// "glslang 12.0.0 / SPIRV-Tools ..." — part of every program's content hash.
std::string compiler_version();

// "aovar 0.1.0 (glslang ... / SPIRV-Tools ...)": --version, and the shard manifests' aovar_version.
std::string tool_version();

}  // namespace aovar::compile
