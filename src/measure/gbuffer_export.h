#pragma once
// `aovar gbuffer`: the G-buffer file of one variant's formats for one view (render/gbuffer_file.h), rendered on
// the Vulkan backend exactly as measure renders that variant's still, so a renderer outside aovar can run the
// rest of the plan on what aovar scored (examples/render_variant, docs/template-contract.md).
#include <filesystem>
#include <string>

#include "compile/run_scope.h"
#include "render/gbuffer_file.h"

namespace aovar::measure {

struct GbufferRequest {
  compile::RunScope scope;           // the manifest and compile cache
  std::string scene = "builtin:atrium";
  std::filesystem::path views_file;  // side file for the scene's views (optional)
  std::string view;                  // empty: the scene's first view
  std::string variant;               // a key of the manifest's space
  render::Extent size{640, 360};
  float radius = 0;                  // world units; 0 = the scene's default (what measure uses)
  std::string device;                // the Vulkan device (render::BackendOptions::device)
};

// Throws std::runtime_error with one line naming the option at fault (an unknown variant or view, a template
// that does not compile) and render::BackendError when the Vulkan device fails.
render::GbufferImage export_gbuffer(const GbufferRequest& request);

}  // namespace aovar::measure
