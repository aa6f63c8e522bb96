#include "plan_runner.h"

#include <cstring>
#include <map>
#include <string>

#include "errors.h"
#include "formats.h"
#include "pipeline.h"
#include "transfers.h"
#include "vk_util.h"

namespace render_variant {
namespace {

const shaders::PassPrograms& vulkan_programs(const shaders::Variant& v, const shaders::Draw& d) {
  return shaders::programs(v, shaders::Target::vulkan, d.pass);
}

// Shader modules by program, destroyed once the pipelines exist (they keep what they need).
struct ShaderModules {
  VkDevice device;
  std::map<const shaders::Program*, VkShaderModule> modules;
  ~ShaderModules() {
    for (auto& [program, module] : modules) vkDestroyShaderModule(device, module, nullptr);
  }
  VkShaderModule of(const shaders::Program* p) {
    auto it = modules.find(p);
    if (it != modules.end()) return it->second;
    VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    ci.codeSize = p->spirv_words * sizeof(std::uint32_t);
    ci.pCode = p->spirv;
    VkShaderModule m = VK_NULL_HANDLE;
    const std::string what = std::string("vkCreateShaderModule of ") + p->key;
    check(vkCreateShaderModule(device, &ci, nullptr, &m), what.c_str());
    return modules[p] = m;
  }
};

// Replaces the plan's clear placeholders by the view's background depth (frame.clip.y) and its negation.
VkClearValue clear_value(const shaders::Texture& t, float background_depth) {
  VkClearValue v{};
  for (int i = 0; i < 4; ++i) {
    float c = t.clear[i];
    if (c == shaders::kClearBackgroundDepth) c = background_depth;
    else if (c == shaders::kClearNegBackgroundDepth) c = -background_depth;
    v.color.float32[i] = c;
  }
  return v;
}

}  // namespace

void require_vulkan_programs(const shaders::Variant& v) {
  if (!v.plan)
    throw InputError(std::string("variant ") + v.key + " has no pass plan in the library (none of its programs "
                     "compiled): choose another variant");
  for (std::size_t i = 0; i < v.plan->draw_count; ++i) {
    const shaders::Draw& d = v.plan->draws[i];
    const shaders::PassPrograms& p = vulkan_programs(v, d);
    if (!d.geometry && (!p.vertex || !p.fragment || !p.vertex->spirv || !p.fragment->spirv))
      throw InputError(std::string("variant ") + v.key + ": the library has no Vulkan SPIR-V for draw " + d.name +
                       ": generate it with --targets vulkan (and --emit cpp)");
  }
}

PlanRunner::PlanRunner(VulkanContext& vk, const shaders::Variant& variant, shaders::Extent size,
                       const std::vector<PlaneUpload>& uploads)
    : vk_(vk), variant_(variant), res_(std::make_unique<PlanResources>(vk, *variant.plan, size)) {
  create_pipelines();
  init_textures(uploads);
}

void PlanRunner::create_pipelines() {
  ShaderModules modules{vk_.device, {}};
  const shaders::Plan& plan = res_->plan;
  for (std::size_t i = 0; i < plan.draw_count; ++i) {
    DrawState& s = res_->draws[i];
    if (!s.runs) continue;
    const shaders::Draw& d = plan.draws[i];
    PipelineDesc desc;
    desc.vertex = modules.of(vulkan_programs(variant_, d).vertex);
    desc.fragment = modules.of(vulkan_programs(variant_, d).fragment);
    for (std::size_t o = 0; o < d.output_count; ++o)
      desc.colour_formats.push_back(d.outputs[o].texture < 0 ? VK_FORMAT_UNDEFINED
                                                             : vk_format(plan.textures[d.outputs[o].texture].format));
    desc.depth = d.depth;
    desc.extent = s.extent;
    desc.layout = vk_.pipeline_layout;
    s.pipeline = create_pipeline(vk_.device, desc);
  }
}

void PlanRunner::init_textures(const std::vector<PlaneUpload>& uploads) {
  Buffer staging = stage_planes(vk_, uploads);
  try {
    VkCommandBuffer cmd = vk_.begin_commands();
    record_texture_init(cmd, *res_, uploads, staging);
    vk_.submit_and_wait(cmd);
  } catch (...) {
    vk_.destroy(staging);
    throw;
  }
  vk_.destroy(staging);
}

// Output `o` of draw `d` in frame parity p as a colour attachment (no view for an unused location), with the barrier
// that makes its level one.
VkRenderingAttachmentInfo PlanRunner::colour_attachment(const shaders::Draw& d, std::size_t o, int p,
                                                        float background_depth,
                                                        std::vector<VkImageMemoryBarrier2>& barriers) const {
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  const shaders::TextureRef& out = d.outputs[o];
  if (out.texture < 0) return a;  // location unused: writes discarded
  const shaders::Texture& t = res_->plan.textures[out.texture];
  const Image& img = res_->image({out.texture, false, 0}, p);
  const uint32_t level = uint32_t(out.level > 0 ? out.level : 0);
  // A fullscreen draw clears its output or rewrites every texel of it: no old contents to keep.
  barriers.push_back(image_barrier(
      img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
          VK_PIPELINE_STAGE_2_COPY_BIT,
      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, level, 1));
  a.imageView = img.level_view(int(level));
  a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  a.loadOp = t.cleared ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  if (t.cleared) a.clearValue = clear_value(t, background_depth);
  return a;
}

// Draw d's depth buffer as its depth attachment, with its barrier; d tests depth (DepthUse other than none).
VkRenderingAttachmentInfo PlanRunner::depth_attachment(const shaders::Draw& d,
                                                       std::vector<VkImageMemoryBarrier2>& barriers) const {
  // write_mask starts its buffer afresh (cleared to 0); skip_background tests against what is there.
  const bool load = d.depth == shaders::DepthUse::skip_background;
  const VkPipelineStageFlags2 tests =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  const Image& z = res_->depth_buffers[d.depth_buffer];
  barriers.push_back(image_barrier(
      z.image, VK_IMAGE_ASPECT_DEPTH_BIT, load ? VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
      VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, tests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, tests,
      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT));
  VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  a.imageView = z.view;
  a.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  a.loadOp = load ? VK_ATTACHMENT_LOAD_OP_LOAD : VK_ATTACHMENT_LOAD_OP_CLEAR;
  a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;  // later draws of the frame test against it
  a.clearValue.depthStencil = {d.depth == shaders::DepthUse::write_mask ? 0.0f : 1.0f, 0};
  return a;
}

// Draw d's outputs back to SHADER_READ_ONLY_OPTIMAL, where every texture rests between draws.
void PlanRunner::release_outputs(VkCommandBuffer cmd, const shaders::Draw& d, int p) const {
  std::vector<VkImageMemoryBarrier2> barriers;
  for (std::size_t o = 0; o < d.output_count; ++o) {
    const shaders::TextureRef& out = d.outputs[o];
    if (out.texture < 0) continue;
    barriers.push_back(image_barrier(res_->image({out.texture, false, 0}, p).image, VK_IMAGE_ASPECT_COLOR_BIT,
                                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                     VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                                     VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                                     VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                                     VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
                                     uint32_t(out.level > 0 ? out.level : 0), 1));
  }
  pipeline_barrier(cmd, barriers.data(), uint32_t(barriers.size()));
}

// Draw i of frame parity p: the fullscreen triangle into its outputs at its viewport, with its depth use.
void PlanRunner::record_draw(VkCommandBuffer cmd, std::size_t i, int p, float background_depth) {
  const shaders::Draw& d = res_->plan.draws[i];
  const DrawState& s = res_->draws[i];
  std::vector<VkImageMemoryBarrier2> barriers;
  std::vector<VkRenderingAttachmentInfo> colour;
  for (std::size_t o = 0; o < d.output_count; ++o)
    colour.push_back(colour_attachment(d, o, p, background_depth, barriers));
  const bool tests_depth = d.depth != shaders::DepthUse::none;
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  if (tests_depth) depth = depth_attachment(d, barriers);
  pipeline_barrier(cmd, barriers.data(), uint32_t(barriers.size()));

  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, s.extent};
  ri.layerCount = 1;
  ri.colorAttachmentCount = uint32_t(colour.size());
  ri.pColorAttachments = colour.data();
  if (tests_depth) ri.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &ri);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s.pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, vk_.pipeline_layout, 0, 1, &s.sets[p], 0, nullptr);
  vkCmdDraw(cmd, 3, 1, 0, 0);  // the fullscreen triangle from gl_VertexIndex
  vkCmdEndRendering(cmd);
  release_outputs(cmd, d, p);
}

void PlanRunner::render(const shaders::FrameBlock& frame) {
  // The previous frame has finished (submit_and_wait): the block may change under no reader.
  std::memcpy(res_->frame_ubo.mapped, &frame, sizeof frame);
  const int p = res_->parities == 2 ? (frame.frame_index[1] & 1) : 0;
  VkCommandBuffer cmd = vk_.begin_commands();
  for (std::size_t i = 0; i < res_->plan.draw_count; ++i)
    if (res_->draws[i].runs) record_draw(cmd, i, p, frame.clip[1]);
  vk_.submit_and_wait(cmd);
  last_parity_ = p;
}

std::vector<float> PlanRunner::read_result(int& width, int& height) {
  if (last_parity_ < 0) throw VulkanError("read_result() before render()");
  const Image& img = res_->image({res_->plan.result, false, 0}, last_parity_);
  width = int(img.extent.width);
  height = int(img.extent.height);
  const VkDeviceSize bytes = VkDeviceSize(width) * height * sizeof(float);
  Buffer readback = vk_.create_buffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
  std::vector<float> pixels(std::size_t(width) * height);
  try {
    VkCommandBuffer cmd = vk_.begin_commands();
    record_result_copy(cmd, img, readback);
    vk_.submit_and_wait(cmd);
    // Row 0 of the image is NDC y = -1, the bottom of the view: PFM's order, no flip.
    std::memcpy(pixels.data(), readback.mapped, bytes);
  } catch (...) {
    vk_.destroy(readback);
    throw;
  }
  vk_.destroy(readback);
  return pixels;
}

}  // namespace render_variant
