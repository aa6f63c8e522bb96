#pragma once
// One interface over Mesa's CPU drivers: "lavapipe" (Vulkan 1.3 through the loader), "osmesa" (OpenGL 4.5
// core through OSMesa) and "gles" (OpenGL ES 3.0 through EGL surfaceless; shares osmesa's GL code, gl_plan.h). A backend uploads a scene, prepares a variant's PipelinePlan, renders
// frames with a time per draw, and reads the result back as floats.
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "image/image.h"
#include "render/frame.h"
#include "render/plan.h"
#include "scene/scene.h"

namespace aovar::render {

// One line for stderr: what failed and what to do ("no Vulkan CPU device (lavapipe) found: install
// mesa-vulkan-drivers (scripts/deps)").
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct BackendOptions {
  int threads = 2;          // LP_NUM_THREADS, set before the driver loads
  bool validation = false;  // lavapipe: enable VK_LAYER_KHRONOS_validation; errors throw BackendError
  // lavapipe: run mediump (RelaxedPrecision) arithmetic in real fp16, as mobile GPUs do, instead of llvmpipe's
  // fp32 (compile/relaxed_fp16.h); needs shaderFloat16. osmesa and gles reject it (their GLSL has no such rewrite).
  // For images only: llvmpipe converts around every fp16 op, so mediump draws get 2-7x slower, not faster.
  bool mediump_as_fp16 = false;
  // lavapipe (the Vulkan backend): which physical device to render on, "--device NAME|INDEX" (device_select.h):
  // empty = the CPU device lavapipe; a number = its index in vkEnumeratePhysicalDevices order; otherwise a
  // case-insensitive substring of its name ("llvmpipe", "radeon"). osmesa and gles ignore it.
  std::string device;
};

struct DeviceInfo {
  std::string backend;      // "lavapipe" / "osmesa" / "gles"
  std::string device;       // "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string api_version;  // "Vulkan 1.3.230" / "OpenGL 4.5 (Core Profile) Mesa 22.3.6" / "OpenGL ES 3.2 Mesa 22.3.6"
  std::string driver;       // "Mesa 22.3.6"
  int threads = 0;          // LP_NUM_THREADS in effect
  bool mediump_fp16 = false;  // mediump arithmetic runs in fp16 (BackendOptions::mediump_as_fp16)
  // The device runs mediump in fp32 (it ignores SPIR-V's RelaxedPrecision; desktop GLSL gives precision
  // qualifiers no meaning, GLSL 4.50 section 4.7): a mediump variant and its highp twin run the same code and
  // are measured once (measure/same_code.h). gles measures it (gl_precision.cpp: ES lets mediump be fp16).
  // `precision` says so for measure.json's devices[].
  bool ignores_relaxed_precision = false;
  std::string precision;    // "mediump runs in fp32 (...)" / "mediump honoured (...)"
  // How draws are timed: "timestamp queries", or for a device without valid ones "wall clock per frame ..."
  // (render() then splits each frame's time evenly over its draws).
  std::string timing;
};

// A prepared variant: its textures, pipelines and per-frame state (progressive history) on one backend.
class PreparedPipeline {
 public:
  virtual ~PreparedPipeline() = default;
  double create_ms = 0;  // time spent creating shaders, pipelines and targets (not the first-draw JIT)
};

class Backend {
 public:
  virtual ~Backend() = default;
  virtual const DeviceInfo& info() const = 0;
  virtual ClipDepth clip_depth() const = 0;

  // Uploads the scene's vertex and index buffers (replacing any previous scene).
  virtual void set_scene(const scene::Scene& scene) = 0;

  // Builds every texture, shader and pipeline of the plan for an output of `size`.
  // Throws BackendError when the driver rejects a shader (naming the program key and the driver's log).
  virtual std::unique_ptr<PreparedPipeline> prepare(const PipelinePlan& plan, Extent size) = 0;

  // Renders one frame and waits for it. Returns the time of each draw in ms, in plan.draws order:
  // lavapipe from timestamp queries (a wall clock per frame where the device has none: DeviceInfo::timing),
  // osmesa and gles from a wall clock around each draw plus glFinish.
  virtual std::vector<double> render(PreparedPipeline& pipeline, const FrameSetup& frame) = 0;

  // The result texture of the last rendered frame, as floats, row 0 = bottom of the view.
  virtual image::FloatImage read_result(PreparedPipeline& pipeline) = 0;

  // Replaces draw `draw`'s AOParams block (same number of floats as the plan gave it) without preparing
  // again: calibration renders one pipeline with many parameter values, and re-preparing would JIT every
  // time. Takes effect from the next render(). Throws BackendError for a bad draw index or size.
  virtual void set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) = 0;

  // Trace builds (trace/trace.h): the storage-buffer words of every draw with trace_words > 0, in draw
  // order, as the last render() left them. Only lavapipe runs trace builds; the others throw BackendError.
  struct TracedDraw {
    std::string name, pass;
    int level = 0;                     // MIP level the draw writes
    std::vector<std::uint32_t> words;  // Draw::trace_words of them
  };
  virtual std::vector<TracedDraw> read_traces(PreparedPipeline& pipeline);
};

std::vector<std::string> backend_names();  // {"lavapipe", "osmesa", "gles"}

// The shader target a backend runs: lavapipe the Vulkan SPIR-V, osmesa the GL 4.5 GLSL, gles the GLSL ES 3.00. Throws BackendError
// naming the backends for an unknown name.
variants::Target target_of(std::string_view backend);

// Throws BackendError (unknown name, missing driver, failed context) with what to do.
std::unique_ptr<Backend> make_backend(std::string_view name, const BackendOptions& options);

// Implementations (render/vulkan/lavapipe.cpp, render/gl/osmesa.cpp, render/gl/gles.cpp).
std::unique_ptr<Backend> make_lavapipe_backend(const BackendOptions& options);
std::unique_ptr<Backend> make_osmesa_backend(const BackendOptions& options);
std::unique_ptr<Backend> make_gles_backend(const BackendOptions& options);

}  // namespace aovar::render
