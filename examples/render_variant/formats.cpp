#include "formats.h"

namespace render_variant {

const char* format_name(shaders::Format f) {
  switch (f) {
    case shaders::Format::r16f: return "r16f";
    case shaders::Format::r32f: return "r32f";
    case shaders::Format::rgba8: return "rgba8";
    case shaders::Format::rg8: return "rg8";
    case shaders::Format::rgba32f: return "rgba32f";
  }
  return "?";
}

VkFormat vk_format(shaders::Format f) {
  switch (f) {
    case shaders::Format::r16f: return VK_FORMAT_R16_SFLOAT;
    case shaders::Format::r32f: return VK_FORMAT_R32_SFLOAT;
    case shaders::Format::rgba8: return VK_FORMAT_R8G8B8A8_UNORM;
    case shaders::Format::rg8: return VK_FORMAT_R8G8_UNORM;
    case shaders::Format::rgba32f: return VK_FORMAT_R32G32B32A32_SFLOAT;
  }
  return VK_FORMAT_UNDEFINED;
}

}  // namespace render_variant
