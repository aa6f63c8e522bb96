// render_variant: renders one variant of an aovar-generated library on one G-buffer, with nothing but that library
// and the Vulkan loader, and writes its AO as aovar writes its images. The reverse check of issue 53: if what an
// engine can build from the generated header alone equals aovar's own image, the header carries everything that
// was scored.
//
//   render_variant KEY GBUFFER_FILE OUT.pfm [--device NAME]
//
// Exit status: 0 written, 1 Vulkan failed on a device that should work, 2 a bad input (one line on stderr).
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "errors.h"
#include "frame_block.h"
#include "gbuffer_file.h"
#include "gbuffer_planes.h"
#include "pfm.h"
#include "plan_runner.h"
#include "shaders.h"
#include "vulkan_context.h"

namespace render_variant {
namespace {

const char* const kUsage = "usage: render_variant KEY GBUFFER_FILE OUT.pfm [--device NAME]";

struct Arguments {
  std::string key, gbuffer, out, device;
  bool help = false;
};

Arguments parse(int argc, char** argv) {
  Arguments a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      a.help = true;
    } else if (arg == "--device") {
      if (i + 1 >= argc)
        throw InputError(std::string("--device needs a NAME (a part of the Vulkan device's name): ") + kUsage);
      a.device = argv[++i];
    } else if (arg.rfind("--device=", 0) == 0) {
      a.device = arg.substr(std::strlen("--device="));
      if (a.device.empty()) throw InputError(std::string("--device= needs a NAME: ") + kUsage);
    } else if (arg.size() > 1 && arg[0] == '-') {
      throw InputError("unknown option " + arg + ": " + kUsage);
    } else {
      positional.push_back(arg);
    }
  }
  if (a.help) return a;
  if (positional.size() != 3)
    throw InputError("expected 3 arguments, got " + std::to_string(positional.size()) + ": " + kUsage);
  a.key = positional[0];
  a.gbuffer = positional[1];
  a.out = positional[2];
  return a;
}

const shaders::Variant& variant_of(const std::string& key) {
  const shaders::Variant* v = shaders::find_variant(key);
  if (!v)
    throw InputError("variant " + key + " is not in this library (" + std::to_string(shaders::variant_count()) +
                     " variants, the first " + (shaders::variant_count() ? shaders::variants()[0].key : "none") +
                     "): generate one that holds it (aovar generate --variants '" + key +
                     "' --emit cpp --targets vulkan --out DIR) and build against it");
  require_vulkan_programs(*v);
  return *v;
}

double mean(const std::vector<float>& pixels) {
  double sum = 0;
  for (float v : pixels) sum += v;
  return pixels.empty() ? 0 : sum / double(pixels.size());
}

int run(const Arguments& a) {
  const shaders::Variant& variant = variant_of(a.key);
  const shaders::Plan& plan = *variant.plan;
  const GbufferFile file = read_gbuffer_file(a.gbuffer);
  const std::vector<PlaneUpload> uploads = match_planes(plan, a.key, file);
  const shaders::Extent size{int(file.width), int(file.height)};

  VulkanContext vk(a.device);
  PlanRunner runner(vk, variant, size, uploads);
  // A still as aovar renders one: frame 0, and frame 1 too for a progressive variant (its other half); the
  // result is read after the last.
  for (int f = 0; f < (plan.progressive ? 2 : 1); ++f) runner.render(still_frame(file.frame, plan, size, f));
  int width = 0, height = 0;
  const std::vector<float> pixels = runner.read_result(width, height);
  write_pfm(a.out, width, height, pixels);
  std::printf("%s: %dx%d on %s, mean visibility %.4f -> %s\n", a.key.c_str(), width, height,
              vk.properties.deviceName, mean(pixels), a.out.c_str());
  return 0;
}

}  // namespace
}  // namespace render_variant

int main(int argc, char** argv) {
  using namespace render_variant;
  try {
    const Arguments a = parse(argc, argv);
    if (a.help) {
      std::printf("%s\nRenders variant KEY of the generated library this program was built with on the G-buffer "
                  "file that `aovar gbuffer` wrote, on the Vulkan CPU device (lavapipe) unless --device names "
                  "another, and writes its AO image as a PFM.\n", kUsage);
      return 0;
    }
    return run(a);
  } catch (const InputError& e) {
    std::fprintf(stderr, "render_variant: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_variant: %s\n", e.what());
    return 1;
  }
}
