#include "compile/relaxed_fp16.h"

#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

#include <stdexcept>
#include <string>

namespace aovar::compile {
namespace {

constexpr std::uint32_t kSpirvMagic = 0x07230203, kRelaxedHeaderWords = 5;  // unity builds: a name of its own
constexpr std::uint32_t kOpDecorate = 71, kOpMemberDecorate = 72, kOpFunction = 54, kRelaxedPrecision = 0;
constexpr spv_target_env kEnv = SPV_ENV_VULKAN_1_2;  // what compile_program emits for the vulkan target

void check_header(const std::vector<std::uint32_t>& spirv) {
  if (spirv.size() < kRelaxedHeaderWords || spirv[0] != kSpirvMagic)
    throw std::runtime_error("mediump->fp16: the input is not a SPIR-V module (no SPIR-V header)");
}

}  // namespace

bool has_relaxed_precision(const std::vector<std::uint32_t>& spirv) {
  if (spirv.size() < kRelaxedHeaderWords || spirv[0] != kSpirvMagic) return false;
  for (std::size_t i = kRelaxedHeaderWords; i < spirv.size();) {
    std::uint32_t words = spirv[i] >> 16, op = spirv[i] & 0xffff;
    if (words == 0 || i + words > spirv.size() || op == kOpFunction) break;  // decorations precede functions
    if ((op == kOpDecorate && words >= 3 && spirv[i + 2] == kRelaxedPrecision) ||
        (op == kOpMemberDecorate && words >= 4 && spirv[i + 3] == kRelaxedPrecision))
      return true;
    i += words;
  }
  return false;
}

std::vector<std::uint32_t> relaxed_precision_to_fp16(const std::vector<std::uint32_t>& spirv) {
  check_header(spirv);
  if (!has_relaxed_precision(spirv)) return spirv;

  std::string log;
  auto consumer = [&log](spv_message_level_t level, const char*, const spv_position_t& pos, const char* message) {
    if (level > SPV_MSG_WARNING) return;
    if (!log.empty()) log += "; ";
    log += message;
    if (pos.index) log += " (word " + std::to_string(pos.index) + ")";
  };
  // The pass converts SSA values only, so function-scope loads and stores go first (glslang ran with its
  // optimizer off); redundant conversions and dead code are removed after. Not simplify-instructions, which the
  // pass's documentation also suggests: it fuses fp32 a * b + c into Fma, which llvmpipe rounds once, so highp
  // math would change too (GTAO/SAO moved by up to 2e-4) and a mediump/highp difference would no longer be
  // fp16's alone. The driver folds the conversions of constants anyway.
  spvtools::Optimizer opt(kEnv);
  opt.SetMessageConsumer(consumer);
  opt.RegisterPass(spvtools::CreateLocalSingleBlockLoadStoreElimPass())
      .RegisterPass(spvtools::CreateLocalSingleStoreElimPass())
      .RegisterPass(spvtools::CreateSSARewritePass())
      .RegisterPass(spvtools::CreateConvertRelaxedToHalfPass())
      .RegisterPass(spvtools::CreateRedundancyEliminationPass())
      .RegisterPass(spvtools::CreateAggressiveDCEPass());
  std::vector<std::uint32_t> out;
  if (!opt.Run(spirv.data(), spirv.size(), &out))  // validates the input first
    throw std::runtime_error("mediump->fp16: spirv-opt failed: " + (log.empty() ? "no message" : log));

  log.clear();
  spvtools::SpirvTools tools(kEnv);
  tools.SetMessageConsumer(consumer);
  if (!tools.Validate(out))
    throw std::runtime_error("mediump->fp16: the converted module does not validate: " +
                             (log.empty() ? "no message" : log));
  return out;
}

}  // namespace aovar::compile
