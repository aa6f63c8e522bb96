#pragma once
// One interface over Mesa's CPU drivers, one folder per API: render/vulkan (Vulkan 1.3 through the loader) and
// render/gl (OpenGL 4.5 core and OpenGL ES 3.0 over one GL executor, gl/gl_plan.h). A backend uploads a scene,
// prepares a variant's PipelinePlan, renders frames with a time per draw, and reads the result back as floats.
// Which backends exist is the registry's (render/registry.cpp): names, targets, factories and availability
// checks are read from it by help text, errors, --backend checks and stress.
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "image/image.h"
#include "render/frame.h"
#include "render/gbuffer_file.h"
#include "render/plan.h"
#include "scene/scene.h"

namespace aovar::render {

// One line for stderr: what failed and what to do ("no Vulkan CPU device found: install mesa-vulkan-drivers
// (scripts/deps)").
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct BackendOptions {
  int threads = 2;          // LP_NUM_THREADS, set before the driver loads
  bool validation = false;  // Vulkan: enable VK_LAYER_KHRONOS_validation; errors throw BackendError
  // Vulkan: run mediump (RelaxedPrecision) arithmetic in real fp16, as mobile GPUs do, instead of llvmpipe's
  // fp32 (compile/relaxed_fp16.h rewrites the SPIR-V); needs shaderFloat16. The GL backends reject it (their
  // GLSL has no such rewrite).
  // For images only: llvmpipe converts around every fp16 op, so mediump draws get 2-7x slower, not faster.
  bool mediump_as_fp16 = false;
  // The Vulkan backend: which physical device to render on, "--device NAME|INDEX" (vulkan/device_select.h):
  // empty = the CPU device; a number = its index in vkEnumeratePhysicalDevices order; otherwise a
  // case-insensitive substring of its name ("llvmpipe", "radeon"). The GL backends ignore it.
  std::string device;
  // Pipelines prepared at one size share one G-buffer per format (render/gbuffer_share.h), drawn only when a
  // frame needs other content than it holds. Off: every pipeline draws its own, as a renderer without sharing
  // would; the images are bit-identical either way (tests/render/test_gbuffer_share.cpp).
  bool share_gbuffer = true;
  // The Vulkan backend: the cache root that keeps shared G-buffers across runs (render::GbufferStore, kind
  // "gbuffer"); empty keeps none. A still uploads a stored G-buffer instead of drawing it.
  std::filesystem::path gbuffer_cache;
};

struct DeviceInfo {
  std::string backend;      // its name in the registry (BackendInfo::name)
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
  // Vulkan from timestamp queries (a wall clock per frame where the device has none: DeviceInfo::timing),
  // GL from a wall clock around each draw plus glFinish. A shared G-buffer is drawn only when it holds other
  // content than this frame needs; its draw's time is that of its latest draw, which this frame reads.
  virtual std::vector<double> render(PreparedPipeline& pipeline, const FrameSetup& frame) = 0;

  // The shared G-buffer `pipeline` reads (render/gbuffer_share.h) as an identity: pipelines with the same one
  // share it. nullptr when the pipeline draws its own (BackendOptions::share_gbuffer off, or a plan that
  // cannot share).
  virtual const void* shared_gbuffer(PreparedPipeline& pipeline);
  // Draws that shared G-buffer for `frame` now, whatever it holds, and returns its time in ms; every render()
  // of a pipeline sharing it reports this time until it is drawn again. The timed rounds draw each G-buffer
  // once a round (measure/timing.h). Throws BackendError for a pipeline without one.
  virtual double render_gbuffer(PreparedPipeline& pipeline, const FrameSetup& frame);
  // How many G-buffers (geometry draws) this backend has drawn, shared or not: what sharing saves, counted.
  virtual std::size_t gbuffer_draws() const { return 0; }

  // The result texture of the last rendered frame, as floats, row 0 = bottom of the view.
  virtual image::FloatImage read_result(PreparedPipeline& pipeline) = 0;
  // The G-buffer the last rendered frame read: the textures its geometry draw writes, then its depth buffer
  // ("zbuffer"), texels as the images hold them (render/gbuffer_file.h). Only the Vulkan backend reads them;
  // the others throw BackendError, as they do before render().
  virtual std::vector<GbufferPlane> read_gbuffer(PreparedPipeline& pipeline);

  // Replaces draw `draw`'s AOParams block (same number of floats as the plan gave it) without preparing
  // again: calibration renders one pipeline with many parameter values, and re-preparing would JIT every
  // time. `draw` indexes the plan that runs at the prepared size (plan_for_size; render::draw_index_at_size finds
  // a draw there by name). Takes effect from the next render(). Throws BackendError for a bad draw index or size.
  virtual void set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) = 0;

  // Trace builds (trace/trace.h): the storage-buffer words of every draw with trace_words > 0, in draw
  // order, as the last render() left them. Only the Vulkan backend runs trace builds; the others throw
  // BackendError.
  struct TracedDraw {
    std::string name, pass;
    int level = 0;                     // MIP level the draw writes
    // Draw::trace_words of them, in the prepared pipeline's memory (a trace is tens of megabytes): valid until it
    // renders again or is destroyed.
    std::span<const std::uint32_t> words;
  };
  virtual std::vector<TracedDraw> read_traces(PreparedPipeline& pipeline);
};

// One backend of the registry.
struct BackendInfo {
  std::string name;         // --backend NAME, DeviceInfo::backend
  variants::Target target;  // the shader target it runs (SPIR-V, GL 4.5 GLSL, GLSL ES 3.00)
  std::function<std::unique_ptr<Backend>(const BackendOptions&)> make;  // throws BackendError
  // Why it cannot start on this machine, with what to install (one line); empty when it can. Cheap: it does
  // not create the backend (which would fix LP_NUM_THREADS for the process).
  std::function<std::string()> unavailable;
  // Several of it may render at once, each made by its own `make` and used on its own thread: a Vulkan device
  // is its own instance, queue and memory; a GL context is current on one thread of a process (OSMesa, EGL).
  bool side_by_side = false;
};

// The backends aovar ships with, the default first (defined in render/registry.cpp, the one list of them).
std::vector<BackendInfo> builtin_backends();

// Unregisters its backend when it goes (tests: a fake backend that no later test sees). Move-only.
class BackendRegistration {
 public:
  explicit BackendRegistration(std::string name) : name_(std::move(name)) {}
  BackendRegistration(BackendRegistration&& other) noexcept : name_(std::exchange(other.name_, {})) {}
  BackendRegistration& operator=(BackendRegistration&&) = delete;
  ~BackendRegistration();

 private:
  std::string name_;  // empty once moved from
};

// Adds a backend after the built-in ones until the handle goes. Throws BackendError for a name already
// registered.
[[nodiscard]] BackendRegistration register_backend(BackendInfo info);

// The backend a run uses unless told: the registry's first built-in one.
std::string default_backend();

std::vector<BackendInfo> registered_backends();  // built-in ones first, in registration order
std::vector<std::string> backend_names();        // their names, in that order
// The names for help text and errors, "a, b, c" (or "a / b / c"); `last`, when given, joins the last two
// ("a, b or c").
std::string backend_list(std::string_view separator = ", ", std::string_view last = {});
// The first backend that runs `target` ("the Vulkan backend"): error text names it. Throws BackendError when none does.
std::string backend_for(variants::Target target);

// The backend's entry; throws BackendError "unknown backend 'NAME' (use A, B or C)" for an unknown name.
BackendInfo backend_info(std::string_view name);

// The shader target a backend runs. Throws BackendError naming the backends for an unknown name.
variants::Target target_of(std::string_view backend);
// The targets `backends` run, each once, in first-use order (what to compile for them). Throws as target_of.
std::vector<variants::Target> targets_of(const std::vector<std::string>& backends);

// Throws BackendError (unknown name, missing driver, failed context) with what to do.
std::unique_ptr<Backend> make_backend(std::string_view name, const BackendOptions& options);

}  // namespace aovar::render
