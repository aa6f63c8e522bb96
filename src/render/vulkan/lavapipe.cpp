// lavapipe backend: executes a PipelinePlan with Vulkan 1.3 dynamic rendering on Mesa's CPU driver (or the
// Vulkan device BackendOptions::device selects) and times every draw with timestamp queries where the device
// has valid ones, else each frame with a wall clock.
//
// Per prepared pipeline: every plan texture (two images when double-buffered) and depth buffer, one graphics
// pipeline per draw, descriptor sets per draw and frame parity, the frame and parameter uniform buffers, a
// timestamp query pool and command buffers recorded once per parity (re-recorded only when the clear values
// or the scene change). Between draws every texture rests in SHADER_READ_ONLY_OPTIMAL.
#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "compile/relaxed_fp16.h"
#include "render/backend.h"
#include "render/gbuffer_share.h"
#include "render/vulkan/lavapipe.h"
#include "render/vulkan/lavapipe_device.h"
#include "render/vulkan/vk_pipeline.h"
#include "util/hash.h"

// Vulkan structs are written `VkFoo foo{VK_STRUCTURE_TYPE_FOO};`: the rest zero-initialised on purpose.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace aovar::render {
namespace {
using namespace lvp;

using vk::kDepthFormat;

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return a > 1 ? (v + a - 1) / a * a : v; }

struct SceneBuffers {
  Buffer positions, normals, indices;
  std::uint32_t index_count = 0;
  std::uint64_t generation = 0;  // 0 = no scene
};

struct TextureImages {
  Image copies[2];
  int count = 1;
};

// A graphics pipeline, shared by every prepared pipeline whose draw needs the same one (LavapipeBackend's
// pipeline reuse); destroyed with its last user.
struct SharedVkPipeline {
  std::shared_ptr<Device> dev;
  VkPipeline pipeline = VK_NULL_HANDLE;
  SharedVkPipeline(std::shared_ptr<Device> d, VkPipeline p) : dev(std::move(d)), pipeline(p) {}
  SharedVkPipeline(const SharedVkPipeline&) = delete;
  SharedVkPipeline& operator=(const SharedVkPipeline&) = delete;
  ~SharedVkPipeline() {
    if (pipeline && dev && dev->device) vkDestroyPipeline(dev->device, pipeline, nullptr);
  }
};

struct DrawState {
  std::shared_ptr<SharedVkPipeline> pipeline;
  VkExtent2D extent{};
  VkRect2D scissor{};         // the viewport's pixels the draw shades (render::Draw::scissor, else all)
  VkDescriptorSet sets[2]{};  // per frame parity (one when nothing is double-buffered)
  VkDeviceSize params_offset = 0, params_range = 0;
  Buffer trace;  // trace builds only: Draw::trace_words words at binding kTrace
};

class LavapipePipeline final : public PreparedPipeline {
 public:
  explicit LavapipePipeline(std::shared_ptr<Device> d) : dev(std::move(d)) {}
  ~LavapipePipeline() override;

  std::shared_ptr<Device> dev;
  Extent size, ao;
  std::vector<Texture> textures;
  std::vector<Draw> draws;  // copies of the plan's textures and draws; the SPIR-V is not kept
  int result = -1;
  int parities = 1;        // 2 when some texture is double-buffered
  bool has_geometry = false;
  // The shared G-buffer this pipeline reads (render/gbuffer_share.h), or null when it draws its own. Its
  // textures and depth buffer are lent: `borrowed` marks them, and this pipeline never destroys them.
  std::shared_ptr<SharedGbuffer> gbuffer;
  std::size_t gbuffer_draw = 0;  // with `gbuffer`: the draw it stands for, which this pipeline does not record
  std::vector<char> borrowed;    // per texture
  int borrowed_depth = -1;       // the depth buffer that is the G-buffer's

  std::vector<TextureImages> images;
  std::vector<Image> depth_buffers;  // per plan depth buffer (D32F)
  std::vector<DrawState> states;
  Buffer frame_ubo, params_ubo, readback;
  VkDescriptorPool descriptor_pool = VK_NULL_HANDLE;
  VkQueryPool queries = VK_NULL_HANDLE;
  VkCommandBuffer frame_cmd[2]{};
  VkCommandBuffer readback_cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;

  struct Recorded {
    bool valid = false;
    float far_plane = 0;
    std::uint64_t scene = 0;
  } recorded[2];
  int last_parity = -1;  // parity of the last rendered frame, -1 before the first
  std::vector<std::uint64_t> stamps;  // reused per frame
  std::vector<double> times;

  // The image a reference names in frame parity p: double-buffered textures are written in copy p, and
  // `previous` reads the other copy (written by the previous frame).
  const Image& image(TextureRef ref, int p) const {
    const TextureImages& t = images[ref.texture];
    if (t.count == 1) return t.copies[0];
    return t.copies[ref.previous ? 1 - p : p];
  }

  // A target's extent: the output's or the AO pass's.
  VkExtent2D extent_of(bool full_resolution) const {
    const Extent e = full_resolution ? size : ao;
    return VkExtent2D{uint32_t(e.width), uint32_t(e.height)};
  }

  void record_frame(int p, float far_plane, const SceneBuffers& scene);

 private:
  VkRenderingAttachmentInfo color_attachment(const Draw& d, const TextureRef& out, int p, float far_plane,
                                             std::vector<VkImageMemoryBarrier2>& barriers) const;
  VkRenderingAttachmentInfo depth_attachment(const Draw& d, std::vector<VkImageMemoryBarrier2>& barriers) const;
};

LavapipePipeline::~LavapipePipeline() {
  if (!dev || !dev->device) return;
  VkDevice d = dev->device;
  vkQueueWaitIdle(dev->queue);  // nothing of ours may still be in flight (a failed wait leaves no trace otherwise)
  for (VkCommandBuffer& c : frame_cmd)
    if (c) vkFreeCommandBuffers(d, dev->pool, 1, &c);
  if (readback_cmd) vkFreeCommandBuffers(d, dev->pool, 1, &readback_cmd);
  if (fence) vkDestroyFence(d, fence, nullptr);
  if (queries) vkDestroyQueryPool(d, queries, nullptr);
  if (descriptor_pool) vkDestroyDescriptorPool(d, descriptor_pool, nullptr);  // frees the sets
  for (DrawState& s : states) {
    s.pipeline.reset();  // after the wait: the last user destroys it
    dev->destroy(s.trace);
  }
  for (std::size_t t = 0; t < images.size(); ++t)
    if (t >= borrowed.size() || !borrowed[t])
      for (Image& i : images[t].copies) dev->destroy(i);
  for (std::size_t b = 0; b < depth_buffers.size(); ++b)
    if (static_cast<int>(b) != borrowed_depth) dev->destroy(depth_buffers[b]);
  dev->destroy(frame_ubo);
  dev->destroy(params_ubo);
  dev->destroy(readback);
}

// Replaces the clear placeholders (plan.h) by the view's background depth (background_depth, frame.h).
VkClearValue clear_value(const Texture& t, float far_plane) {
  VkClearValue v{};
  for (int i = 0; i < 4; ++i) {
    float c = t.clear[i];
    if (c == kClearFar) c = far_plane;
    else if (c == kClearNegFar) c = -far_plane;
    v.color.float32[i] = c;
  }
  return v;
}

// The attachment of output `out` of draw `d` in frame parity `p`, and the barrier that makes its level a
// colour attachment (appended to `barriers`).
VkRenderingAttachmentInfo LavapipePipeline::color_attachment(const Draw& d, const TextureRef& out, int p,
                                                             float far_plane,
                                                             std::vector<VkImageMemoryBarrier2>& barriers) const {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  if (out.texture < 0) {  // location unused: no view, writes discarded
    a.imageView = VK_NULL_HANDLE;
    return a;
  }
  const Texture& t = textures[out.texture];
  const Image& img = image(TextureRef{out.texture, false}, p);
  const uint32_t level = static_cast<uint32_t>(std::max(out.level, 0));
  // Cleared targets and fullscreen outputs (every texel rewritten) need no old contents.
  bool load = !t.cleared && d.geometry;
  barriers.push_back(image_barrier(
      img.image, VK_IMAGE_ASPECT_COLOR_BIT,
      load ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
          VK_PIPELINE_STAGE_2_COPY_BIT,
      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, level, 1));
  a.imageView = img.level_view(static_cast<int>(level));
  a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  a.loadOp = t.cleared ? VK_ATTACHMENT_LOAD_OP_CLEAR : load ? VK_ATTACHMENT_LOAD_OP_LOAD
                                                            : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  if (t.cleared) a.clearValue = clear_value(t, far_plane);
  return a;
}

// Draw `d`'s depth attachment (none when it tests no depth) and its barrier (appended to `barriers`).
VkRenderingAttachmentInfo LavapipePipeline::depth_attachment(const Draw& d,
                                                             std::vector<VkImageMemoryBarrier2>& barriers) const {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  if (d.depth == DepthUse::none) return a;
  // geometry and write_mask start the buffer afresh; skip_background reads what they left.
  const bool load = d.depth == DepthUse::skip_background;
  const VkPipelineStageFlags2 tests =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  const Image& z = depth_buffers[d.depth_buffer];
  barriers.push_back(image_barrier(
      z.image, VK_IMAGE_ASPECT_DEPTH_BIT, load ? VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
      VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, tests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, tests,
      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT));
  a.imageView = z.view;
  a.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  a.loadOp = load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;  // later draws of the frame test against it
  a.clearValue.depthStencil = {d.depth == DepthUse::write_mask ? 0.0f : 1.0f, 0};
  return a;
}

void LavapipePipeline::record_frame(int p, float far_plane, const SceneBuffers& scene) {
  VkCommandBuffer cmd = frame_cmd[p];
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  if (queries) vkCmdResetQueryPool(cmd, queries, 0, static_cast<uint32_t>(2 * draws.size()));

  std::vector<VkImageMemoryBarrier2> barriers;
  std::vector<VkRenderingAttachmentInfo> attachments;
  for (std::size_t i = 0; i < draws.size(); ++i) {
    const Draw& d = draws[i];
    const DrawState& s = states[i];

    // The start stamp goes before the barrier: lavapipe executes a barrier by flushing and waiting for the
    // rasteriser, so the stamp lands in a scene of its own, taken when the previous draw has finished, and
    // not among this draw's tiles (llvmpipe stamps per tile and keeps the latest).
    // A GPU writes a TOP_OF_PIPE stamp as soon as the command is reached, while the previous draw may still
    // run: there the start stamp waits for all earlier work (Device::start_stamp_stage), so the draws' times
    // sum to the frame's without counting an overlap twice. Not measured on a GPU here (none was lent).
    if (queries) vkCmdWriteTimestamp2(cmd, dev->start_stamp_stage, queries, static_cast<uint32_t>(2 * i));
    if (gbuffer && i == gbuffer_draw) {  // the shared G-buffer's draw: render() draws it when stale
      if (queries)
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, queries, static_cast<uint32_t>(2 * i + 1));
      continue;
    }

    barriers.clear();
    attachments.clear();
    for (const TextureRef& out : d.outputs) attachments.push_back(color_attachment(d, out, p, far_plane, barriers));
    const VkRenderingAttachmentInfo depth_target = depth_attachment(d, barriers);
    pipeline_barrier(cmd, barriers.data(), static_cast<uint32_t>(barriers.size()));

    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, s.extent};
    ri.layerCount = 1;
    ri.colorAttachmentCount = static_cast<uint32_t>(attachments.size());
    ri.pColorAttachments = attachments.data();
    if (d.depth != DepthUse::none) ri.pDepthAttachment = &depth_target;
    vkCmdBeginRendering(cmd, &ri);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s.pipeline->pipeline);
    const VkViewport viewport{0, 0, float(s.extent.width), float(s.extent.height), 0.0f, 1.0f};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &s.scissor);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, dev->pipeline_layout, 0, 1, &s.sets[p % parities],
                            0, nullptr);
    if (d.geometry) {
      VkBuffer vb[2] = {scene.positions.buffer, scene.normals.buffer};
      VkDeviceSize offsets[2] = {0, 0};
      vkCmdBindVertexBuffers(cmd, 0, 2, vb, offsets);
      vkCmdBindIndexBuffer(cmd, scene.indices.buffer, 0, VK_INDEX_TYPE_UINT32);
      vkCmdDrawIndexed(cmd, scene.index_count, 1, 0, 0, 0);
    } else {
      vkCmdDraw(cmd, 3, 1, 0, 0);  // fullscreen triangle, no vertex input
    }
    vkCmdEndRendering(cmd);
    // The end stamp flushes the draw first (any stage but TOP_OF_PIPE does on lavapipe).
    if (queries)
      vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, queries, static_cast<uint32_t>(2 * i + 1));

    barriers.clear();
    for (const TextureRef& out : d.outputs) {
      if (out.texture < 0) continue;
      barriers.push_back(image_barrier(image(TextureRef{out.texture, false}, p).image, VK_IMAGE_ASPECT_COLOR_BIT,
                                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                       VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                       VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                                       VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                                       VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                                       VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
                                       static_cast<uint32_t>(std::max(out.level, 0)), 1));
    }
    pipeline_barrier(cmd, barriers.data(), static_cast<uint32_t>(barriers.size()));
  }
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  recorded[p] = {true, far_plane, scene.generation};
}

class LavapipeBackend final : public Backend {
 public:
  explicit LavapipeBackend(const BackendOptions& options)
      : dev_(std::make_shared<Device>(options)), share_gbuffer_(options.share_gbuffer),
        store_(options.gbuffer_cache, "lavapipe " + dev_->info.device + " " + dev_->info.driver) {}
  ~LavapipeBackend() override {
    vkDeviceWaitIdle(dev_->device);
    release_scene();
  }

  const DeviceInfo& info() const override { return dev_->info; }
  ClipDepth clip_depth() const override { return ClipDepth::zero_to_one; }

  void set_scene(const scene::Scene& scene) override;
  std::unique_ptr<PreparedPipeline> prepare(const PipelinePlan& plan, Extent size) override;
  std::vector<double> render(PreparedPipeline& pipeline, const FrameSetup& frame) override;
  const void* shared_gbuffer(PreparedPipeline& pipeline) override { return ours(pipeline).gbuffer.get(); }
  double render_gbuffer(PreparedPipeline& pipeline, const FrameSetup& frame) override;
  std::size_t gbuffer_draws() const override { return gbuffer_draws_; }
  image::FloatImage read_result(PreparedPipeline& pipeline) override;
  std::vector<GbufferPlane> read_gbuffer(PreparedPipeline& pipeline) override;
  std::vector<TracedDraw> read_traces(PreparedPipeline& pipeline) override;
  void set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) override;

 private:
  LavapipePipeline& ours(PreparedPipeline& p) {
    auto* lp = dynamic_cast<LavapipePipeline*>(&p);
    if (!lp || lp->dev != dev_) throw BackendError("lavapipe: this pipeline was prepared by another backend");
    return *lp;
  }
  void release_scene() {
    dev_->destroy(scene_.positions);
    dev_->destroy(scene_.normals);
    dev_->destroy(scene_.indices);
    scene_ = SceneBuffers{};
  }
  // prepare() of the plan at its size; with `split`, the G-buffer is the pool's.
  std::unique_ptr<LavapipePipeline> prepare_at_size(const PipelinePlan& plan, Extent size, const GbufferSplit* split);
  // Draws pp's shared G-buffer for `frame` when stale (always with `force`); returns its time.
  double ensure_gbuffer(LavapipePipeline& pp, const FrameSetup& frame, bool force);
  void upload_gbuffer(LavapipePipeline& gp, const std::vector<GbufferPlane>& planes);
  // The steps of prepare(), in order.
  void lend_gbuffer(const GbufferSplit& split, LavapipePipeline& pp);
  void create_images(const PipelinePlan& plan, LavapipePipeline& pp);
  void read_draw_times(LavapipePipeline& pp) const;
  std::string read_image(LavapipePipeline& pp, const Image& img, VkImageAspectFlags aspect, VkImageLayout rest,
                         std::uint32_t texel_bytes);
  void create_uniform_buffers(const PipelinePlan& plan, LavapipePipeline& pp);
  void create_descriptor_sets(const PipelinePlan& plan, LavapipePipeline& pp);
  void write_descriptor_set(const Draw& draw, LavapipePipeline& pp, DrawState& s, int parity);
  void write_trace_binding(const Draw& draw, LavapipePipeline& pp, DrawState& s, int parity);
  void create_pipelines(const PipelinePlan& plan, LavapipePipeline& pp);
  // What create_graphics_pipeline gets for `draw`; throws BackendError for a scissor outside the viewport.
  vk::PipelineDesc describe_pipeline(const PipelinePlan& plan, const Draw& draw, VkExtent2D extent,
                                     const std::vector<VkShaderModule>& modules) const;
  VkPipeline create_pipeline(const PipelinePlan& plan, const Draw& draw, const vk::PipelineDesc& desc);
  // The pipeline of `draw` (described by `desc`): a recent one with the same key (its shaders' code, formats,
  // depth use; the viewport is dynamic), else created and kept.
  std::shared_ptr<SharedVkPipeline> reuse_or_create(const PipelinePlan& plan, const Draw& draw,
                                                    const vk::PipelineDesc& desc,
                                                    const std::vector<std::string>& code_hashes);
  void create_frame_objects(const PipelinePlan& plan, LavapipePipeline& pp);
  void init_textures(LavapipePipeline& pp);

  std::shared_ptr<Device> dev_;
  SceneBuffers scene_;
  bool share_gbuffer_ = true;
  GbufferStore store_;
  GbufferPool gbuffers_;  // after dev_: destroyed first, while the device lives
  std::size_t gbuffer_draws_ = 0;
  // Pipeline reuse. Most draws of a variant are another variant's (one blur program serves many methods, every
  // blur variant has its method's AO draw), and lavapipe compiles each pipeline's shaders with LLVM at creation
  // (15 % of the screen's stills on Sponza), so the most recently used pipelines are kept by key and handed out
  // again. The key is the pipeline's whole description (describe_pipeline) but the viewport and scissor, which
  // are dynamic state: the same key, the same pipeline, at any extent (an AO draw at 1/1, 1/2 and 1/4).
  struct KeptPipeline {
    std::shared_ptr<SharedVkPipeline> pipeline;
    std::uint64_t last_use = 0;
  };
  static constexpr std::size_t kKeptPipelines = 256;
  std::map<std::string, KeptPipeline> kept_pipelines_;
  std::uint64_t pipeline_uses_ = 0;
};

void LavapipeBackend::set_scene(const scene::Scene& scene) {
  if (scene.normals.size() != scene.positions.size())
    throw BackendError(fmt::format("lavapipe: scene {} has {} normals for {} positions", scene.name,
                                   scene.normals.size(), scene.positions.size()));
  if (scene.indices.size() % 3 != 0)
    throw BackendError(fmt::format("lavapipe: scene {} has {} indices, not a triangle list", scene.name,
                                   scene.indices.size()));
  // A CPU driver reads out-of-range vertices from host memory: refuse them here rather than crash there.
  for (std::uint32_t i : scene.indices)
    if (i >= scene.positions.size())
      throw BackendError(fmt::format("lavapipe: scene {} has index {} past its {} vertices", scene.name, i,
                                     scene.positions.size()));
  vkDeviceWaitIdle(dev_->device);  // recorded frames may still name the old buffers
  release_scene();
  auto upload = [&](const void* data, std::size_t bytes, VkBufferUsageFlags usage) {
    Buffer b = dev_->create_buffer(std::max<std::size_t>(bytes, 16), usage);  // no zero-sized buffers
    if (bytes) std::memcpy(b.mapped, data, bytes);
    return b;
  };
  scene_.positions = upload(scene.positions.data(), scene.positions.size() * sizeof(glm::vec3),
                            VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  scene_.normals = upload(scene.normals.data(), scene.normals.size() * sizeof(glm::vec3),
                          VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
  scene_.indices = upload(scene.indices.data(), scene.indices.size() * sizeof(std::uint32_t),
                          VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
  scene_.index_count = static_cast<std::uint32_t>(scene.indices.size());
  scene_.generation = next_scene_generation();
  store_.set_scene(scene_.generation, scene.content_hash);
}

// Shader modules by plan shader index, destroyed when the pipelines are built (they keep what they need).
struct ShaderModules {
  VkDevice device;
  std::vector<VkShaderModule> modules;
  ~ShaderModules() {
    for (VkShaderModule m : modules)
      if (m) vkDestroyShaderModule(device, m, nullptr);
  }
};

// A shader's SPIR-V with mediump arithmetic rewritten to fp16 (BackendOptions::mediump_as_fp16).
std::vector<std::uint32_t> fp16_code(const Shader& sh) {
  try {
    return compile::relaxed_precision_to_fp16(sh.spirv);
  } catch (const std::runtime_error& e) {
    throw BackendError(fmt::format("lavapipe: program {}: {}", sh.program_key, e.what()));
  }
}

void LavapipeBackend::create_pipelines(const PipelinePlan& plan, LavapipePipeline& pp) {
  ShaderModules shaders{dev_->device, std::vector<VkShaderModule>(plan.shaders.size(), VK_NULL_HANDLE)};
  std::vector<std::string> code_hashes(plan.shaders.size());
  for (std::size_t i = 0; i < plan.shaders.size(); ++i) {
    const Shader& sh = plan.shaders[i];
    if (sh.spirv.empty())
      throw BackendError(fmt::format("lavapipe: program {} has no SPIR-V (compile the vulkan target)", sh.program_key));
    std::vector<std::uint32_t> fp16;
    if (dev_->info.mediump_fp16) fp16 = fp16_code(sh);
    const std::vector<std::uint32_t>& code = dev_->info.mediump_fp16 ? fp16 : sh.spirv;
    code_hashes[i] = util::hash_hex({reinterpret_cast<const char*>(code.data()), code.size() * sizeof(std::uint32_t)});
    VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    ci.codeSize = code.size() * sizeof(std::uint32_t);
    ci.pCode = code.data();
    VkResult r = vkCreateShaderModule(dev_->device, &ci, nullptr, &shaders.modules[i]);
    if (r != VK_SUCCESS) {
      shaders.modules[i] = VK_NULL_HANDLE;
      throw BackendError(fmt::format("lavapipe: the driver rejected program {} ({})", sh.program_key, result_name(r)));
    }
    dev_->check_validation(fmt::format("shader module creation of program {}", sh.program_key));
  }
  for (std::size_t i = 0; i < plan.draws.size(); ++i) {
    const Draw& dr = plan.draws[i];
    if (pp.gbuffer && i == pp.gbuffer_draw) continue;  // the shared G-buffer's own pipeline draws it
    DrawState& state = pp.states[i];
    const vk::PipelineDesc desc = describe_pipeline(plan, dr, state.extent, shaders.modules);
    state.scissor = desc.scissor.extent.width > 0 ? desc.scissor : VkRect2D{{0, 0}, state.extent};
    state.pipeline = reuse_or_create(plan, dr, desc, code_hashes);
    dev_->check_validation(fmt::format("pipeline creation of draw {} ({} + {})", dr.name,
                                       plan.shaders[dr.vertex].program_key, plan.shaders[dr.fragment].program_key));
  }
}

std::shared_ptr<SharedVkPipeline> LavapipeBackend::reuse_or_create(const PipelinePlan& plan, const Draw& dr,
                                                                   const vk::PipelineDesc& desc,
                                                                   const std::vector<std::string>& code_hashes) {
  // The key is the description create_pipeline gets, with the shaders' code for their per-prepare modules; the
  // viewport and scissor are dynamic (set while recording), so no extent is in it.
  std::string key = fmt::format("{}|{}|{}|{}|{}|{}", code_hashes.at(dr.vertex), code_hashes.at(dr.fragment),
                                static_cast<int>(desc.depth), desc.geometry, fmt::join(desc.colour_formats, ","),
                                desc.flags);
  KeptPipeline& kept = kept_pipelines_[key];
  kept.last_use = ++pipeline_uses_;
  if (!kept.pipeline) {
    kept.pipeline = std::make_shared<SharedVkPipeline>(dev_, create_pipeline(plan, dr, desc));
    if (kept_pipelines_.size() > kKeptPipelines)  // drop the least recently used (a user keeps it alive)
      kept_pipelines_.erase(std::min_element(kept_pipelines_.begin(), kept_pipelines_.end(), [](const auto& a, const auto& b) {
        return a.second.last_use < b.second.last_use;
      }));
  }
  return kept.pipeline;
}

vk::PipelineDesc LavapipeBackend::describe_pipeline(const PipelinePlan& plan, const Draw& dr, VkExtent2D extent,
                                                   const std::vector<VkShaderModule>& modules) const {
  vk::PipelineDesc desc;
  desc.vertex = modules[dr.vertex];
  desc.fragment = modules[dr.fragment];
  desc.geometry = dr.geometry;
  desc.colour_formats.assign(dr.outputs.size(), VK_FORMAT_UNDEFINED);
  for (std::size_t o = 0; o < dr.outputs.size(); ++o)
    if (dr.outputs[o].texture >= 0) desc.colour_formats[o] = vk::format_of(plan.textures[dr.outputs[o].texture].format);
  desc.depth = dr.depth;
  desc.extent = extent;
  if (const auto& [x0, y0, w, h] = dr.scissor; w > 0) {
    if (x0 < 0 || y0 < 0 || h <= 0 || unsigned(x0 + w) > extent.width || unsigned(y0 + h) > extent.height)
      throw BackendError(fmt::format("lavapipe: draw {} has a scissor {}x{}+{}+{} outside its {}x{} viewport", dr.name,
                                     w, h, x0, y0, extent.width, extent.height));
    desc.scissor = {{x0, y0}, {unsigned(w), unsigned(h)}};
  }
  desc.layout = dev_->pipeline_layout;
  desc.dynamic_viewport = true;
  return desc;
}

VkPipeline LavapipeBackend::create_pipeline(const PipelinePlan& plan, const Draw& dr, const vk::PipelineDesc& desc) {
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkResult r = vk::create_graphics_pipeline(dev_->device, desc, &pipeline);
  if (r != VK_SUCCESS)
    throw BackendError(fmt::format("lavapipe: the driver rejected the pipeline of draw {} ({} + {}): {}", dr.name,
                                   plan.shaders[dr.vertex].program_key, plan.shaders[dr.fragment].program_key,
                                   result_name(r)));
  return pipeline;
}

// Defines every texel before the first frame: double-buffered textures start open (1.0) so that frame 0's
// history is defined, the others start at 0. Leaves everything in SHADER_READ_ONLY_OPTIMAL.
void LavapipeBackend::init_textures(LavapipePipeline& pp) {
  VkCommandBuffer cmd = pp.frame_cmd[0];
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  std::vector<VkImageMemoryBarrier2> barriers;
  std::vector<std::size_t> own;  // the shared G-buffer's textures hold its content: left alone
  for (std::size_t i = 0; i < pp.images.size(); ++i)
    if (!pp.borrowed[i]) own.push_back(i);
  for (std::size_t i : own)
    for (int c = 0; c < pp.images[i].count; ++c)
      barriers.push_back(image_barrier(pp.images[i].copies[c].image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                       VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE,
                                       VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                                       VK_ACCESS_2_TRANSFER_WRITE_BIT));
  pipeline_barrier(cmd, barriers.data(), static_cast<uint32_t>(barriers.size()));
  VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, 1};
  for (std::size_t i : own) {
    float v = pp.textures[i].double_buffered ? 1.0f : 0.0f;
    VkClearColorValue value{{v, v, v, v}};
    for (int c = 0; c < pp.images[i].count; ++c)
      vkCmdClearColorImage(cmd, pp.images[i].copies[c].image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1, &range);
  }
  for (auto& b : barriers) {
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    b.srcStageMask = VK_PIPELINE_STAGE_2_CLEAR_BIT;
    b.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    b.dstStageMask = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    b.dstAccessMask = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT |
                      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
  }
  pipeline_barrier(cmd, barriers.data(), static_cast<uint32_t>(barriers.size()));
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  dev_->submit_and_wait(cmd, pp.fence);
}

std::unique_ptr<PreparedPipeline> LavapipeBackend::prepare(const PipelinePlan& full_plan, Extent size) {
  const PipelinePlan plan = plan_for_size(full_plan, size);
  const auto split = share_gbuffer_ ? split_gbuffer(plan, size) : std::nullopt;
  return prepare_at_size(plan, size, split ? &*split : nullptr);
}

std::unique_ptr<LavapipePipeline> LavapipeBackend::prepare_at_size(const PipelinePlan& plan, Extent size,
                                                                   const GbufferSplit* split) {
  auto start = std::chrono::steady_clock::now();
  validate_plan(plan, "lavapipe");
  uint32_t max_dim = dev_->properties.limits.maxImageDimension2D;
  if (size.width <= 0 || size.height <= 0 || uint32_t(size.width) > max_dim || uint32_t(size.height) > max_dim)
    throw BackendError(fmt::format("lavapipe: output size {}x{} is out of range (1..{} per side)", size.width,
                                   size.height, max_dim));
  auto pp = std::make_unique<LavapipePipeline>(dev_);  // on a throw its destructor frees what exists
  pp->size = size;
  pp->ao = ao_extent(size, plan.resolution);
  pp->textures = plan.textures;
  pp->draws = plan.draws;
  pp->result = plan.result;
  for (const Texture& t : plan.textures)
    if (t.double_buffered) pp->parities = 2;
  for (const Draw& dr : plan.draws) pp->has_geometry |= dr.geometry;
  pp->borrowed.assign(plan.textures.size(), 0);

  if (split) lend_gbuffer(*split, *pp);
  create_images(plan, *pp);
  create_uniform_buffers(plan, *pp);
  create_descriptor_sets(plan, *pp);
  create_pipelines(plan, *pp);
  create_frame_objects(plan, *pp);
  init_textures(*pp);
  dev_->check_validation(fmt::format("prepare of {}", plan.variant));
  pp->create_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return pp;
}

// The pool's G-buffer for `split` (prepared on first use), its images lent to pp's G-buffer textures and depth
// buffer (create_images leaves those alone).
void LavapipeBackend::lend_gbuffer(const GbufferSplit& split, LavapipePipeline& pp) {
  pp.gbuffer = gbuffers_.get(split, pp.size, [&](const PipelinePlan& g) { return prepare_at_size(g, pp.size, nullptr); });
  pp.gbuffer_draw = split.draw;
  const auto& g = static_cast<const LavapipePipeline&>(*pp.gbuffer->pipeline);
  pp.images.resize(pp.textures.size());
  for (std::size_t i = 0; i < split.texture.size(); ++i)
    if (split.texture[i] >= 0) {
      pp.images[i] = g.images[split.texture[i]];
      pp.borrowed[i] = 1;
    }
  pp.borrowed_depth = split.depth_buffer;
}

// Every plan texture (two images when double-buffered) and depth buffer, but those lent by a shared G-buffer.
void LavapipeBackend::create_images(const PipelinePlan& plan, LavapipePipeline& pp) {
  const VkFormatFeatureFlags needed = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                  VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  pp.images.resize(plan.textures.size());
  for (std::size_t i = 0; i < plan.textures.size(); ++i) {
    if (pp.borrowed[i]) continue;
    const Texture& t = plan.textures[i];
    VkFormat f = vk::format_of(t.format);
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(dev_->physical, f, &fp);
    if ((fp.optimalTilingFeatures & needed) != needed)
      throw BackendError(fmt::format("lavapipe: {} cannot render to and sample format {} (texture {})",
                                     dev_->info.device, format_name(t.format), t.name));
    pp.images[i].count = t.double_buffered ? 2 : 1;
    for (int c = 0; c < pp.images[i].count; ++c)
      pp.images[i].copies[c] = dev_->create_image(pp.extent_of(t.full_resolution), f, usage, VK_IMAGE_ASPECT_COLOR_BIT,
                                                  static_cast<uint32_t>(std::max(t.levels, 1)));
  }
  for (std::size_t b = 0; b < plan.depth_buffers.size(); ++b)
    pp.depth_buffers.push_back(
        static_cast<int>(b) == pp.borrowed_depth
            ? static_cast<const LavapipePipeline&>(*pp.gbuffer->pipeline).depth_buffers.at(0)
            : dev_->create_image(pp.extent_of(plan.depth_buffers[b].full_resolution), kDepthFormat,
                                 VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                     VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                                 VK_IMAGE_ASPECT_DEPTH_BIT));
}

// AOFrame (rewritten each frame) and every draw's AOParams at aligned offsets of one buffer; also each
// draw's viewport extent.
void LavapipeBackend::create_uniform_buffers(const PipelinePlan& plan, LavapipePipeline& pp) {
  pp.frame_ubo = dev_->create_buffer(sizeof(FrameBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  VkDeviceSize align = std::max<VkDeviceSize>(dev_->properties.limits.minUniformBufferOffsetAlignment, 16);
  pp.states.resize(plan.draws.size());
  VkDeviceSize params_size = 0;
  for (std::size_t i = 0; i < plan.draws.size(); ++i) {
    DrawState& s = pp.states[i];
    s.extent = pp.extent_of(plan.draws[i].full_resolution);
    s.extent.width = std::max(1u, s.extent.width >> plan.draws[i].level);
    s.extent.height = std::max(1u, s.extent.height >> plan.draws[i].level);
    s.params_offset = params_size;
    // std140 float members sit at 4 * i; a draw without a block still gets a small range for its binding.
    s.params_range = align_up(std::max<VkDeviceSize>(plan.draws[i].params.size() * sizeof(float), 16), 16);
    params_size = align_up(params_size + s.params_range, align);
  }
  pp.params_ubo = dev_->create_buffer(params_size, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  std::memset(pp.params_ubo.mapped, 0, params_size);
  for (std::size_t i = 0; i < plan.draws.size(); ++i)
    if (!plan.draws[i].params.empty())
      std::memcpy(static_cast<char*>(pp.params_ubo.mapped) + pp.states[i].params_offset,
                  plan.draws[i].params.data(), plan.draws[i].params.size() * sizeof(float));
}

// One descriptor set per draw and frame parity.
void LavapipeBackend::create_descriptor_sets(const PipelinePlan& plan, LavapipePipeline& pp) {
  uint32_t sets = static_cast<uint32_t>(plan.draws.size()) * pp.parities;
  VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kFirstSampler * sets},
                                   {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, (kBindingCount - kFirstSampler) * sets},
                                   {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, sets}};
  VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dpci.maxSets = sets;
  dpci.poolSizeCount = 3;
  dpci.pPoolSizes = sizes;
  check(vkCreateDescriptorPool(dev_->device, &dpci, nullptr, &pp.descriptor_pool), "vkCreateDescriptorPool");
  for (std::size_t i = 0; i < plan.draws.size(); ++i)
    for (int p = 0; p < pp.parities; ++p) write_descriptor_set(plan.draws[i], pp, pp.states[i], p);
}

// Allocates and fills draw `dr`'s set for frame parity `p`: the two uniform blocks, its inputs at their
// sampler bindings and the dummy texture at every other.
void LavapipeBackend::write_descriptor_set(const Draw& dr, LavapipePipeline& pp, DrawState& s, int p) {
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pp.descriptor_pool;
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &dev_->set_layout;
  check(vkAllocateDescriptorSets(dev_->device, &ai, &s.sets[p]), "vkAllocateDescriptorSets");
  VkDescriptorBufferInfo buffers[kFirstSampler];
  buffers[shadergen::binding::kFrame] = {pp.frame_ubo.buffer, 0, sizeof(FrameBlock)};
  buffers[shadergen::binding::kParams] = {pp.params_ubo.buffer, s.params_offset, s.params_range};
  VkDescriptorImageInfo samplers[kBindingCount - kFirstSampler];
  for (auto& si : samplers) si = {dev_->sampler, dev_->dummy.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  for (const auto& [binding, ref] : dr.inputs)
    samplers[binding - kFirstSampler].imageView =
        ref.level < 0 ? pp.image(ref, p).view : pp.image(ref, p).level_view(ref.level);
  VkWriteDescriptorSet w[kBindingCount];
  for (uint32_t b = 0; b < kBindingCount; ++b) {
    w[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w[b].dstSet = s.sets[p];
    w[b].dstBinding = b;
    w[b].descriptorCount = 1;
    if (b < kFirstSampler) {
      w[b].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
      w[b].pBufferInfo = &buffers[b];
    } else {
      w[b].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      w[b].pImageInfo = &samplers[b - kFirstSampler];
    }
  }
  vkUpdateDescriptorSets(dev_->device, kBindingCount, w, 0, nullptr);
  if (dr.trace_words > 0) write_trace_binding(dr, pp, s, p);
}

// A traced draw's storage buffer at binding kTrace, filled with all-ones words (gpu::kNoRead) except word 0,
// the overflow count: slots a pixel does not fill read as "no read".
void LavapipeBackend::write_trace_binding(const Draw& dr, LavapipePipeline& pp, DrawState& s, int p) {
  if (!dev_->fragment_stores)
    throw BackendError(fmt::format("lavapipe: {} lacks fragmentStoresAndAtomics, which fetch traces need",
                                   dev_->info.device));
  const VkDeviceSize bytes = VkDeviceSize(dr.trace_words) * sizeof(std::uint32_t);
  if (!s.trace.buffer) {
    if (bytes > dev_->properties.limits.maxStorageBufferRange)
      throw BackendError(fmt::format("lavapipe: the trace of draw {} needs {} MB, over the device's storage buffer "
                                     "range of {} MB: trace a smaller window", dr.name, bytes >> 20,
                                     dev_->properties.limits.maxStorageBufferRange >> 20));
    s.trace = dev_->create_buffer(bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    std::memset(s.trace.mapped, 0xFF, bytes);
    std::memset(s.trace.mapped, 0, sizeof(std::uint32_t));
  }
  VkDescriptorBufferInfo info{s.trace.buffer, 0, bytes};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = s.sets[p];
  w.dstBinding = kTraceBinding;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  w.pBufferInfo = &info;
  vkUpdateDescriptorSets(dev_->device, 1, &w, 0, nullptr);
}

// Timestamps, command buffers (one per parity and one for the read-back), fence, read-back buffer.
void LavapipeBackend::create_frame_objects(const PipelinePlan& plan, LavapipePipeline& pp) {
  VkDevice d = dev_->device;
  if (dev_->timestamps) {  // else no pool: frames are timed by wall clock (render)
    VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qci.queryCount = static_cast<uint32_t>(2 * plan.draws.size());
    check(vkCreateQueryPool(d, &qci, nullptr, &pp.queries), "vkCreateQueryPool");
  }
  VkCommandBuffer cmds[3]{};
  VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cai.commandPool = dev_->pool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = static_cast<uint32_t>(pp.parities) + 1;
  check(vkAllocateCommandBuffers(d, &cai, cmds), "vkAllocateCommandBuffers");
  for (int p = 0; p < pp.parities; ++p) pp.frame_cmd[p] = cmds[p];
  pp.readback_cmd = cmds[pp.parities];
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(d, &fci, nullptr, &pp.fence), "vkCreateFence");
  if (plan.result >= 0) {  // a G-buffer's plan has no result (gbuffer_share.h)
    VkExtent2D result_extent = pp.extent_of(plan.textures[plan.result].full_resolution);
    pp.readback = dev_->create_buffer(VkDeviceSize(result_extent.width) * result_extent.height * sizeof(float),
                                      VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
  }
  pp.stamps.resize(2 * plan.draws.size());
  pp.times.resize(plan.draws.size());
}

// Each draw's time from its pair of timestamps (the frame's fence has been waited for).
void LavapipeBackend::read_draw_times(LavapipePipeline& pp) const {
  uint32_t n = static_cast<uint32_t>(pp.stamps.size());
  check(vkGetQueryPoolResults(dev_->device, pp.queries, 0, n, n * sizeof(std::uint64_t), pp.stamps.data(),
                              sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  double ns_per_tick = dev_->properties.limits.timestampPeriod;
  for (std::size_t i = 0; i < pp.times.size(); ++i) {
    std::uint64_t ticks = (pp.stamps[2 * i + 1] - pp.stamps[2 * i]) & dev_->timestamp_mask;
    pp.times[i] = double(ticks) * ns_per_tick * 1e-6;
  }
}

std::vector<double> LavapipeBackend::render(PreparedPipeline& pipeline, const FrameSetup& frame) {
  LavapipePipeline& pp = ours(pipeline);
  if (!frame.view) throw BackendError("lavapipe: render() needs a view");
  if (pp.has_geometry && scene_.generation == 0) throw BackendError("lavapipe: render() before set_scene()");
  if (pp.gbuffer) ensure_gbuffer(pp, frame, false);
  FrameBlock block = make_frame_block(frame, pp.size, pp.ao, ClipDepth::zero_to_one);
  std::memcpy(pp.frame_ubo.mapped, &block, sizeof block);  // the previous frame finished: fence waited
  if (pp.has_geometry && !pp.gbuffer) ++gbuffer_draws_;

  int p = pp.parities == 2 ? (frame.frame & 1) : 0;
  // Linear depth clears to the finite background depth (frame.h), never to an infinite far plane.
  float far_plane = background_depth(frame.view->far_plane);
  const auto& rec = pp.recorded[p];
  if (!rec.valid || rec.far_plane != far_plane || rec.scene != scene_.generation) {
    pp.recorded[p].valid = false;
    pp.record_frame(p, far_plane, scene_);
  }
  const auto submitted = std::chrono::steady_clock::now();
  dev_->submit_and_wait(pp.frame_cmd[p], pp.fence);
  pp.last_parity = p;
  if (pp.queries) {
    read_draw_times(pp);
  } else {
    const double frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - submitted).count();
    std::fill(pp.times.begin(), pp.times.end(), frame_ms / static_cast<double>(std::max<std::size_t>(1, pp.times.size())));
  }
  if (pp.gbuffer) pp.times[pp.gbuffer_draw] = pp.gbuffer->last_ms;
  if (dev_->validation_failed()) dev_->check_validation(fmt::format("frame {}", frame.frame));
  return pp.times;
}

double LavapipeBackend::ensure_gbuffer(LavapipePipeline& pp, const FrameSetup& frame, bool force) {
  const FrameBlock block = make_frame_block(frame, pp.size, pp.ao, ClipDepth::zero_to_one);
  const FrameBlock file_block = make_frame_block(frame, pp.size, pp.size, ClipDepth::zero_to_one);  // gbuffer_file.h
  const GbufferOps ops{[&](PreparedPipeline& g) { return render(g, frame); },
                       [&](PreparedPipeline& g) { return read_gbuffer(g); },
                       [&](PreparedPipeline& g, const std::vector<GbufferPlane>& planes) { upload_gbuffer(ours(g), planes); }};
  return gbuffers_.ensure(*pp.gbuffer, gbuffer_content(block, scene_.generation), file_block, force, ops, &store_);
}

// A stored G-buffer into G-buffer pipeline `gp`'s images: the planes of its one draw's outputs, then its depth
// buffer (GbufferStore checked names, formats and size), left as a draw leaves them.
void LavapipeBackend::upload_gbuffer(LavapipePipeline& gp, const std::vector<GbufferPlane>& planes) {
  const Draw& d = gp.draws.front();
  struct Target {
    const Image* image;
    VkImageAspectFlags aspect;
    VkImageLayout rest;
  };
  std::vector<Target> targets;
  for (const TextureRef& o : d.outputs)
    if (o.texture >= 0)
      targets.push_back({&gp.image(TextureRef{o.texture, false}, 0), VK_IMAGE_ASPECT_COLOR_BIT,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  targets.push_back({&gp.depth_buffers.at(d.depth_buffer), VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL});
  if (targets.size() != planes.size())
    throw BackendError(fmt::format("lavapipe: a stored G-buffer of {} planes for {} targets", planes.size(), targets.size()));
  std::vector<VkDeviceSize> offsets;
  VkDeviceSize total = 0;
  for (const GbufferPlane& p : planes) {
    offsets.push_back(total);
    total = align_up(total + p.texels.size(), 16);
  }
  Buffer staging = dev_->create_buffer(std::max<VkDeviceSize>(total, 16), VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  for (std::size_t i = 0; i < planes.size(); ++i)
    std::memcpy(static_cast<char*>(staging.mapped) + offsets[i], planes[i].texels.data(), planes[i].texels.size());

  VkCommandBuffer cmd = gp.readback_cmd;
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  const VkPipelineStageFlags2 users = VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT |
                                      VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const Target& t = targets[i];
    // UNDEFINED: every texel is replaced, whatever the image held.
    auto to_dst = image_barrier(t.image->image, t.aspect, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                users, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    pipeline_barrier(cmd, &to_dst, 1);
    VkBufferImageCopy copy{};
    copy.bufferOffset = offsets[i];
    copy.imageSubresource = {t.aspect, 0, 0, 1};
    copy.imageExtent = {t.image->extent.width, t.image->extent.height, 1};
    vkCmdCopyBufferToImage(cmd, staging.buffer, t.image->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    auto to_rest = image_barrier(t.image->image, t.aspect, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, t.rest,
                                 VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, users,
                                 VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
    pipeline_barrier(cmd, &to_rest, 1);
  }
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  dev_->submit_and_wait(cmd, gp.fence);
  dev_->destroy(staging);
  dev_->check_validation("G-buffer upload");
}

double LavapipeBackend::render_gbuffer(PreparedPipeline& pipeline, const FrameSetup& frame) {
  LavapipePipeline& pp = ours(pipeline);
  if (!pp.gbuffer) return Backend::render_gbuffer(pipeline, frame);
  if (!frame.view) throw BackendError("lavapipe: render_gbuffer() needs a view");
  return ensure_gbuffer(pp, frame, true);
}

// Level 0 of `img` (resting in `rest`) as the image holds it, `texel_bytes` a texel, rows from the bottom of the
// view (frame.h: row 0 is NDC y = -1, no flip).
std::string LavapipeBackend::read_image(LavapipePipeline& pp, const Image& img, VkImageAspectFlags aspect,
                                        VkImageLayout rest, std::uint32_t texel_bytes) {
  const VkDeviceSize bytes = VkDeviceSize(img.extent.width) * img.extent.height * texel_bytes;
  Buffer own;  // the result's read-back buffer, or one of this size for a wider texel
  if (pp.readback.size < bytes) own = dev_->create_buffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
  const Buffer& target = own.buffer ? own : pp.readback;
  const bool depth = aspect == VK_IMAGE_ASPECT_DEPTH_BIT;
  const VkPipelineStageFlags2 written = depth ? VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT
                                              : VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
  const VkAccessFlags2 write = depth ? VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT : VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;

  VkCommandBuffer cmd = pp.readback_cmd;
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
  auto to_src = image_barrier(img.image, aspect, rest, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, written, write,
                              VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  pipeline_barrier(cmd, &to_src, 1);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {aspect, 0, 0, 1};
  copy.imageExtent = {img.extent.width, img.extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target.buffer, 1, &copy);
  auto back = image_barrier(img.image, aspect, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rest, VK_PIPELINE_STAGE_2_COPY_BIT,
                            VK_ACCESS_2_NONE,
                            VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT |
                                VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT,
                            VK_ACCESS_2_NONE);
  VkBufferMemoryBarrier2 to_host{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
  to_host.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
  to_host.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
  to_host.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
  to_host.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
  to_host.srcQueueFamilyIndex = to_host.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_host.buffer = target.buffer;
  to_host.size = VK_WHOLE_SIZE;
  pipeline_barrier(cmd, &back, 1, &to_host, 1);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  dev_->submit_and_wait(cmd, pp.fence);
  std::string out(static_cast<const char*>(target.mapped), static_cast<std::size_t>(bytes));
  dev_->destroy(own);
  dev_->check_validation("read-back");
  return out;
}

image::FloatImage LavapipeBackend::read_result(PreparedPipeline& pipeline) {
  LavapipePipeline& pp = ours(pipeline);
  if (pp.last_parity < 0) throw BackendError("lavapipe: read_result() before render()");
  if (pp.result < 0) throw BackendError("lavapipe: read_result() of a G-buffer, which has no result");
  const Image& img = pp.image(TextureRef{pp.result, false}, pp.last_parity);
  const std::string bytes = read_image(pp, img, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                       sizeof(float));
  image::FloatImage out;
  out.width = static_cast<int>(img.extent.width);
  out.height = static_cast<int>(img.extent.height);
  out.pixels.resize(std::size_t(out.width) * out.height);
  std::memcpy(out.pixels.data(), bytes.data(), bytes.size());
  return out;
}

std::vector<GbufferPlane> LavapipeBackend::read_gbuffer(PreparedPipeline& pipeline) {
  LavapipePipeline& pp = ours(pipeline);
  if (pp.last_parity < 0) throw BackendError("lavapipe: read_gbuffer() before render()");
  const auto geometry = std::find_if(pp.draws.begin(), pp.draws.end(), [](const Draw& d) { return d.geometry; });
  if (geometry == pp.draws.end()) throw BackendError("lavapipe: read_gbuffer() of a plan without a geometry draw");
  std::vector<GbufferPlane> planes;
  for (const TextureRef& out : geometry->outputs) {
    if (out.texture < 0) continue;
    const Texture& t = pp.textures[out.texture];
    GbufferPlane p{t.name, passplan::format_name(t.format), static_cast<std::uint32_t>(passplan::format_bytes(t.format)), {}};
    p.texels = read_image(pp, pp.image(TextureRef{out.texture, false}, pp.last_parity), VK_IMAGE_ASPECT_COLOR_BIT,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, p.texel_bytes);
    planes.push_back(std::move(p));
  }
  GbufferPlane z{"zbuffer", "d32f", 4, {}};
  z.texels = read_image(pp, pp.depth_buffers.at(geometry->depth_buffer), VK_IMAGE_ASPECT_DEPTH_BIT,
                        VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, z.texel_bytes);
  planes.push_back(std::move(z));
  return planes;
}

}  // namespace

std::vector<Backend::TracedDraw> LavapipeBackend::read_traces(PreparedPipeline& pipeline) {
  auto& pp = static_cast<LavapipePipeline&>(pipeline);
  if (pp.last_parity < 0) throw BackendError("lavapipe: read_traces() before render()");
  std::vector<TracedDraw> out;
  for (std::size_t i = 0; i < pp.draws.size(); ++i) {
    const Draw& d = pp.draws[i];
    if (d.trace_words <= 0) continue;
    // Host-coherent memory, read after render() waited on the frame's fence.
    const auto* words = static_cast<const std::uint32_t*>(pp.states[i].trace.mapped);
    out.push_back({d.name, d.pass, d.level, std::span<const std::uint32_t>(words, std::size_t(d.trace_words))});
  }
  return out;
}

void LavapipeBackend::set_params(PreparedPipeline& pipeline, std::size_t draw, const std::vector<float>& params) {
  LavapipePipeline& pp = ours(pipeline);
  if (draw >= pp.draws.size() || params.size() != pp.draws[draw].params.size())
    throw BackendError(fmt::format("lavapipe: set_params: draw {} of {} takes {} floats, got {}", draw,
                                   pp.draws.size(), draw < pp.draws.size() ? pp.draws[draw].params.size() : 0,
                                   params.size()));
  // The recorded frames read the block from host-visible memory: no frame may be in flight while it changes.
  check(vkQueueWaitIdle(dev_->queue), "vkQueueWaitIdle");
  if (!params.empty()) std::memcpy(static_cast<char*>(pp.params_ubo.mapped) + pp.states[draw].params_offset, params.data(),
              params.size() * sizeof(float));
  pp.draws[draw].params = params;
}

std::unique_ptr<Backend> make_lavapipe_backend(const BackendOptions& options) {
  return std::make_unique<LavapipeBackend>(options);
}

}  // namespace aovar::render
