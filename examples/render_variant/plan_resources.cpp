#include "plan_resources.h"

#include <algorithm>
#include <cstring>

#include "errors.h"
#include "formats.h"
#include "vk_util.h"

namespace render_variant {
namespace {

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize a) { return a > 1 ? (v + a - 1) / a * a : v; }

}  // namespace

PlanResources::PlanResources(VulkanContext& vk, const shaders::Plan& p, shaders::Extent frame_size)
    : plan(p), size(frame_size), ao(shaders::ao_extent(frame_size, p.resolution)), vk_(vk) {
  for (std::size_t i = 0; i < plan.texture_count; ++i)
    if (plan.textures[i].double_buffered) parities = 2;
  draws.resize(plan.draw_count);
  for (std::size_t i = 0; i < plan.draw_count; ++i) {
    const shaders::Draw& d = plan.draws[i];
    draws[i].runs = !d.geometry && shaders::draw_runs_at(plan, d, size);
    // The viewport: the frame's or the AO extent, each side shifted right by the level the draw writes.
    draws[i].extent = extent_of(d.full_resolution);
    draws[i].extent.width = std::max(1u, draws[i].extent.width >> d.level);
    draws[i].extent.height = std::max(1u, draws[i].extent.height >> d.level);
  }
  try {
    create_images();
    create_depth_buffers();
    create_uniform_buffers();
    create_descriptor_sets();
  } catch (...) {
    release();
    throw;
  }
}

PlanResources::~PlanResources() { release(); }

const Image& PlanResources::image(const shaders::TextureRef& ref, int parity) const {
  const TextureImages& t = textures.at(ref.texture);
  if (t.count == 1) return t.copies[0];
  return t.copies[ref.previous ? 1 - parity : parity];
}

VkExtent2D PlanResources::extent_of(bool full_resolution) const {
  const shaders::Extent e = full_resolution ? size : ao;
  return VkExtent2D{uint32_t(e.width), uint32_t(e.height)};
}

// Colour targets are also sampled, copied from (the result) and copied or cleared into (the G-buffer planes and
// the first frame's contents), as in aovar.
void PlanResources::create_images() {
  const VkFormatFeatureFlags needed = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                  VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  textures.resize(plan.texture_count);
  for (std::size_t i = 0; i < plan.texture_count; ++i) {
    const shaders::Texture& t = plan.textures[i];
    const VkFormat f = vk_format(t.format);
    VkFormatProperties fp;
    vkGetPhysicalDeviceFormatProperties(vk_.physical, f, &fp);
    if ((fp.optimalTilingFeatures & needed) != needed)
      throw InputError(std::string("the Vulkan device ") + vk_.properties.deviceName + " cannot render to and sample " +
                       format_name(t.format) + " (texture " + t.name + "): pick another with --device NAME");
    // A texture keeps the MIP levels its extent can hold (draw_runs_at skips the draws into the others).
    const VkExtent2D e = extent_of(t.full_resolution);
    const int levels = std::min(std::max(t.levels, 1), shaders::mip_levels_at({int(e.width), int(e.height)}));
    textures[i].count = t.double_buffered ? 2 : 1;
    for (int c = 0; c < textures[i].count; ++c)
      textures[i].copies[c] = vk_.create_image(e, f, usage, VK_IMAGE_ASPECT_COLOR_BIT, uint32_t(levels));
  }
}

// D32F; the geometry draw's depth buffer also takes the G-buffer file's zbuffer plane by a copy.
void PlanResources::create_depth_buffers() {
  for (std::size_t b = 0; b < plan.depth_buffer_count; ++b) {
    VkImageUsageFlags usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    for (std::size_t i = 0; i < plan.draw_count; ++i)
      if (plan.draws[i].geometry && plan.draws[i].depth_buffer == int(b)) usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    depth_buffers.push_back(vk_.create_image(extent_of(plan.depth_buffers[b].full_resolution), kDepthFormat, usage,
                                             VK_IMAGE_ASPECT_DEPTH_BIT));
  }
}

// AOFrame (written before each frame) in its own buffer; every draw's AOParams block at an aligned offset of one
// buffer: std140 floats at 4 * i, and a draw without a block still gets a 16-byte range of zeros for its binding.
void PlanResources::create_uniform_buffers() {
  frame_ubo = vk_.create_buffer(sizeof(shaders::FrameBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  const VkDeviceSize align = std::max<VkDeviceSize>(vk_.properties.limits.minUniformBufferOffsetAlignment, 16);
  VkDeviceSize total = 0;
  for (std::size_t i = 0; i < plan.draw_count; ++i) {
    draws[i].params_offset = total;
    draws[i].params_range = align_up(std::max<VkDeviceSize>(plan.draws[i].block_size * sizeof(float), 16), 16);
    total = align_up(total + draws[i].params_range, align);
  }
  params_ubo = vk_.create_buffer(total, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
  std::memset(params_ubo.mapped, 0, total);
  for (std::size_t i = 0; i < plan.draw_count; ++i)
    if (plan.draws[i].block_size > 0)
      std::memcpy(static_cast<char*>(params_ubo.mapped) + draws[i].params_offset, plan.draws[i].block_values,
                  plan.draws[i].block_size * sizeof(float));
}

void PlanResources::create_descriptor_sets() {
  const uint32_t sets = uint32_t(plan.draw_count) * uint32_t(parities);
  VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kFirstSampler * sets},
                                   {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, (kBindingCount - kFirstSampler) * sets}};
  VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dpci.maxSets = sets;
  dpci.poolSizeCount = 2;
  dpci.pPoolSizes = sizes;
  check(vkCreateDescriptorPool(vk_.device, &dpci, nullptr, &pool_), "vkCreateDescriptorPool");
  for (std::size_t i = 0; i < plan.draw_count; ++i)
    if (draws[i].runs)
      for (int p = 0; p < parities; ++p) write_descriptor_set(plan.draws[i], draws[i], p);
}

// The two uniform blocks, the draw's inputs at their sampler bindings (a level input as a view of that level
// alone, else a view of every level) and the dummy texture at every other sampler binding.
void PlanResources::write_descriptor_set(const shaders::Draw& d, DrawState& s, int parity) {
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pool_;
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &vk_.set_layout;
  check(vkAllocateDescriptorSets(vk_.device, &ai, &s.sets[parity]), "vkAllocateDescriptorSets");
  VkDescriptorBufferInfo buffers[kFirstSampler] = {{frame_ubo.buffer, 0, sizeof(shaders::FrameBlock)},
                                                   {params_ubo.buffer, s.params_offset, s.params_range}};
  VkDescriptorImageInfo samplers[kBindingCount - kFirstSampler];
  for (auto& si : samplers) si = {vk_.sampler, vk_.dummy.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  for (std::size_t i = 0; i < d.input_count; ++i) {
    const shaders::Input& in = d.inputs[i];
    if (in.binding < int(kFirstSampler) || in.binding >= int(kBindingCount))
      throw InputError(std::string("draw ") + d.name + " reads binding " + std::to_string(in.binding) +
                       ", outside the template contract's samplers (2..7): regenerate the library with this aovar");
    const Image& img = image(in.texture, parity);
    samplers[in.binding - kFirstSampler].imageView = in.texture.level < 0 ? img.view : img.level_view(in.texture.level);
  }
  VkWriteDescriptorSet w[kBindingCount];
  for (uint32_t b = 0; b < kBindingCount; ++b) {
    w[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w[b].dstSet = s.sets[parity];
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
  vkUpdateDescriptorSets(vk_.device, kBindingCount, w, 0, nullptr);
}

void PlanResources::release() {
  vkDeviceWaitIdle(vk_.device);
  for (DrawState& s : draws)
    if (s.pipeline) vkDestroyPipeline(vk_.device, s.pipeline, nullptr);
  if (pool_) vkDestroyDescriptorPool(vk_.device, pool_, nullptr);  // frees the sets
  pool_ = VK_NULL_HANDLE;
  for (TextureImages& t : textures)
    for (Image& i : t.copies) vk_.destroy(i);
  for (Image& i : depth_buffers) vk_.destroy(i);
  vk_.destroy(frame_ubo);
  vk_.destroy(params_ubo);
  draws.clear();
}

}  // namespace render_variant
