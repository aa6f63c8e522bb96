#include "compile/glslang_compiler.h"

#include "util/version.h"  // generated: AOVAR_VERSION from project(aovar VERSION ...)

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <spirv-tools/libspirv.hpp>

#include <mutex>
#include <stdexcept>
#include <sstream>

#include "util/hash.h"

namespace aovar::compile {
using variants::StageKind;
using variants::Target;

void initialise_compiler() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

std::string compiler_version() {
  glslang::Version v = glslang::GetVersion();
  return "glslang " + std::to_string(v.major) + "." + std::to_string(v.minor) + "." + std::to_string(v.patch) +
         v.flavor + " / " + spvSoftwareVersionString();
}

std::string tool_version() { return std::string("aovar ") + AOVAR_VERSION + " (" + compiler_version() + ")"; }

namespace {

// glslang writes "ERROR: 3:42: 'x' : undeclared identifier"; we keep source string, line and text.
void parse_log(const std::string& log, std::vector<Diagnostic>& out) {
  std::istringstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    Diagnostic d;
    std::string rest;
    if (line.rfind("ERROR: ", 0) == 0) {
      rest = line.substr(7);
    } else if (line.rfind("WARNING: ", 0) == 0) {
      d.severity = Diagnostic::Severity::warning;
      rest = line.substr(9);
    } else {
      continue;
    }
    if (rest.find("compilation errors.") != std::string::npos || rest.find("compilation terminated") == 0) continue;
    int src = 0, ln = 0, consumed = 0;
    if (std::sscanf(rest.c_str(), "%d:%d: %n", &src, &ln, &consumed) == 2 && consumed > 0) {
      d.source = src;
      d.line = ln;
      rest = rest.substr(consumed);
    }
    d.message = rest;
    bool dup = false;
    for (const auto& e : out) dup |= e.source == d.source && e.line == d.line && e.message == d.message;
    if (!dup) out.push_back(std::move(d));
  }
}

struct FrontEnd {
  glslang::EShClient client;
  glslang::EShTargetClientVersion client_version;
  glslang::EShTargetLanguageVersion spirv_version;
  EShMessages messages;
  bool emit_spirv;
  spv_target_env validate_env;
};

EShLanguage language(StageKind s) { return s == StageKind::vertex ? EShLangVertex : EShLangFragment; }

bool is_float_type(int gl_type) { return gl_type == 0x1406; /* GL_FLOAT */ }

// spirv-val's messages for `spirv` ("" when valid). Friendly names (%name instead of %42 in messages) cost a
// second parse of the whole binary on every call, a quarter of the validation time, and only a failure
// shows them: so valid binaries are checked without them and a failure is validated again with them, for
// the same message as always.
std::string validate_once(const std::vector<std::uint32_t>& spirv, spv_target_env env) {
  spvtools::SpirvTools tools(env);
  spvtools::ValidatorOptions quiet;
  quiet.SetFriendlyNames(false);
  if (tools.Validate(spirv.data(), spirv.size(), quiet)) return {};
  std::string errors;
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t& pos, const char* m) {
    errors += "spirv-val: " + std::string(m) + " (word " + std::to_string(pos.index) + ")";
  });
  tools.Validate(spirv);
  return errors.empty() ? "spirv-val failed" : errors;
}

std::string validate(const std::vector<std::uint32_t>& spirv, spv_target_env env, ValidationMemo* memo) {
  if (!memo) return validate_once(spirv, env);
  std::string key = std::to_string(static_cast<int>(env)) + ":" +
                    util::hash_hex(std::string_view(reinterpret_cast<const char*>(spirv.data()), spirv.size() * 4));
  if (auto known = memo->find(key)) return *known;
  std::string errors = validate_once(spirv, env);
  memo->remember(key, errors);
  return errors;
}

// Parses, links and (optionally) emits and validates SPIR-V. Appends diagnostics; returns success.
bool run(const std::string& source, StageKind stage, const FrontEnd& fe, CompileOutput& out, bool reflect,
         std::string* preprocessed, ValidationMemo* memo) {
  EShLanguage lang = language(stage);
  glslang::TShader shader(lang);
  const char* text = source.c_str();
  int length = static_cast<int>(source.size());
  shader.setStringsWithLengths(&text, &length, 1);
  shader.setEnvInput(glslang::EShSourceGlsl, lang, fe.client, fe.client == glslang::EShClientNone ? 0 : 100);
  if (fe.client != glslang::EShClientNone) {
    shader.setEnvClient(fe.client, fe.client_version);
    shader.setEnvTarget(glslang::EShTargetSpv, fe.spirv_version);
  }
  const TBuiltInResource* resources = GetDefaultResources();
  if (preprocessed) {  // a separate TShader: one TShader is parsed once
    glslang::TShader pre(lang);
    pre.setStringsWithLengths(&text, &length, 1);
    pre.setEnvInput(glslang::EShSourceGlsl, lang, fe.client, 0);
    glslang::TShader::ForbidIncluder no_includes;
    if (!pre.preprocess(resources, 100, ENoProfile, false, false, fe.messages, preprocessed, no_includes)) {
      parse_log(pre.getInfoLog(), out.diagnostics);
      return false;
    }
  }
  bool ok = shader.parse(resources, 100, false, fe.messages);
  parse_log(shader.getInfoLog(), out.diagnostics);
  if (!ok) return false;
  glslang::TProgram program;
  program.addShader(&shader);
  ok = program.link(fe.messages);
  parse_log(program.getInfoLog(), out.diagnostics);
  if (!ok) return false;
  if (reflect && program.buildReflection(EShReflectionAllBlockVariables)) {
    for (int i = 0; i < program.getNumUniformVariables(); ++i) {
      const glslang::TObjectReflection& u = program.getUniform(i);
      for (const char* prefix : {"AOParams.", "params."}) {
        if (u.name.rfind(prefix, 0) == 0)
          out.params_block.push_back({u.name.substr(std::string(prefix).size()), is_float_type(u.glDefineType)});
      }
    }
  }
  if (!fe.emit_spirv) return true;

  glslang::SpvOptions options;
  options.generateDebugInfo = false;
  options.disableOptimizer = true;
  options.validate = false;  // validated below with the target's environment
  spv::SpvBuildLogger logger;
  out.spirv.clear();
  glslang::GlslangToSpv(*program.getIntermediate(lang), out.spirv, &logger, &options);
  if (std::string msg = logger.getAllMessages(); !msg.empty())
    out.diagnostics.push_back({Diagnostic::Severity::warning, -1, 0, "SPIR-V back end: " + msg});
  if (std::string errors = validate(out.spirv, fe.validate_env, memo); !errors.empty()) {
    out.diagnostics.push_back({Diagnostic::Severity::error, -1, 0, errors});
    return false;
  }
  return true;
}

}  // namespace

std::optional<std::string> ValidationMemo::find(const std::string& key) const {
  std::lock_guard lock(mutex_);
  auto it = results_.find(key);
  if (it == results_.end()) return std::nullopt;
  return it->second;
}

void ValidationMemo::remember(const std::string& key, const std::string& errors) {
  std::lock_guard lock(mutex_);
  results_.emplace(key, errors);
}

std::string spirv_errors(const std::vector<std::uint32_t>& spirv, Target target, ValidationMemo* memo) {
  if (target == Target::gles30) return spirv.empty() ? "" : "gles30 programs have no SPIR-V";
  if (spirv.empty()) return "no SPIR-V";
  return validate(spirv, target == Target::vulkan ? SPV_ENV_VULKAN_1_2 : SPV_ENV_OPENGL_4_5, memo);
}

CompileOutput compile_program(const std::string& source, StageKind stage, Target target, ValidationMemo* memo) {
  initialise_compiler();
  CompileOutput out;
  const auto cascading = static_cast<EShMessages>(EShMsgCascadingErrors);
  switch (target) {
    case Target::vulkan: {
      FrontEnd fe{glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2, glslang::EShTargetSpv_1_5,
                  static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules | cascading), true,
                  SPV_ENV_VULKAN_1_2};
      out.ok = run(source, stage, fe, out, true, nullptr, memo);
      break;
    }
    case Target::gl45: {
      FrontEnd glsl{glslang::EShClientNone, glslang::EShTargetClientVersion{}, glslang::EShTargetLanguageVersion{},
                    cascading, false, SPV_ENV_OPENGL_4_5};
      FrontEnd spirv{glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450, glslang::EShTargetSpv_1_0,
                     static_cast<EShMessages>(EShMsgSpvRules | cascading), true, SPV_ENV_OPENGL_4_5};
      out.ok = run(source, stage, glsl, out, true, nullptr, memo) && run(source, stage, spirv, out, false, nullptr, memo);
      break;
    }
    case Target::gles30: {
      FrontEnd fe{glslang::EShClientNone, glslang::EShTargetClientVersion{}, glslang::EShTargetLanguageVersion{},
                  cascading, false, SPV_ENV_UNIVERSAL_1_0};
      std::string pre;
      out.ok = run(source, stage, fe, out, true, &pre, memo);
      // Preprocessed text without #line/blank lines: equal text = same program whatever the defines were.
      std::string normalised;
      std::istringstream in(pre);
      for (std::string line; std::getline(in, line);) {
        if (line.find_first_not_of(" \t") == std::string::npos || line.rfind("#line", 0) == 0) continue;
        normalised += line;
        normalised += '\n';
      }
      out.identity = util::hash_hex(normalised);
      break;
    }
  }
  if (out.ok && target != Target::gles30)
    out.identity = util::hash_hex(std::string_view(reinterpret_cast<const char*>(out.spirv.data()),
                                                   out.spirv.size() * sizeof(std::uint32_t)));
  if (!out.ok) out.spirv.clear();
  return out;
}

std::string preprocess_es(const std::string& source, StageKind stage) {
  initialise_compiler();
  glslang::TShader shader(language(stage));
  const char* text = source.c_str();
  const int length = static_cast<int>(source.size());
  shader.setStringsWithLengths(&text, &length, 1);
  shader.setEnvInput(glslang::EShSourceGlsl, language(stage), glslang::EShClientNone, 0);
  glslang::TShader::ForbidIncluder no_includes;
  std::string out;
  if (!shader.preprocess(GetDefaultResources(), 300, EEsProfile, false, false, EShMsgDefault, &out, no_includes))
    throw std::runtime_error("glslang preprocessor: " + std::string(shader.getInfoLog()));
  return out;
}

}  // namespace aovar::compile
