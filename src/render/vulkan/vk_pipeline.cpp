#include "render/vulkan/vk_pipeline.h"

#include <glm/vec3.hpp>

// Vulkan structs are filled by sType and the members that matter; the rest is zero on purpose.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace aovar::render::vk {
namespace {

VkPipelineDepthStencilStateCreateInfo depth_state(DepthUse use) {
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = use != DepthUse::none;
  ds.depthWriteEnable = use == DepthUse::geometry || use == DepthUse::write_mask;
  ds.depthCompareOp = use == DepthUse::write_mask        ? VK_COMPARE_OP_ALWAYS
                      : use == DepthUse::skip_background ? VK_COMPARE_OP_NOT_EQUAL
                                                         : VK_COMPARE_OP_LESS;
  return ds;
}

}  // namespace

VkFormat format_of(Format f) {
  switch (f) {
    case Format::r16f: return VK_FORMAT_R16_SFLOAT;
    case Format::r32f: return VK_FORMAT_R32_SFLOAT;
    case Format::rgba8: return VK_FORMAT_R8G8B8A8_UNORM;
    case Format::rg8: return VK_FORMAT_R8G8_UNORM;
    case Format::rgba32f: return VK_FORMAT_R32G32B32A32_SFLOAT;
  }
  return VK_FORMAT_UNDEFINED;
}

VkResult create_graphics_pipeline(VkDevice device, const PipelineDesc& d, VkPipeline* pipeline) {
  VkPipelineShaderStageCreateInfo stages[2]{};
  stages[0] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, d.vertex, "main"};
  stages[1] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT, d.fragment, "main"};
  // Geometry draws read positions (location 0) and normals (location 1), one buffer each.
  VkVertexInputBindingDescription vb[2] = {{0, sizeof(glm::vec3), VK_VERTEX_INPUT_RATE_VERTEX},
                                           {1, sizeof(glm::vec3), VK_VERTEX_INPUT_RATE_VERTEX}};
  VkVertexInputAttributeDescription va[2] = {{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}, {1, 1, VK_FORMAT_R32G32B32_SFLOAT, 0}};
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  if (d.geometry) {
    vi.vertexBindingDescriptionCount = vi.vertexAttributeDescriptionCount = 2;
    vi.pVertexBindingDescriptions = vb;
    vi.pVertexAttributeDescriptions = va;
  }
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkViewport viewport{0, 0, float(d.extent.width), float(d.extent.height), 0.0f, 1.0f};
  const VkRect2D scissor = d.scissor.extent.width > 0 ? d.scissor : VkRect2D{{0, 0}, d.extent};
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = vp.scissorCount = 1;
  vp.pViewports = &viewport;
  vp.pScissors = &scissor;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;  // the fullscreen triangle's winding flips with the API's y direction
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  const VkPipelineDepthStencilStateCreateInfo ds = depth_state(d.depth);
  std::vector<VkPipelineColorBlendAttachmentState> blend(d.colour_formats.size());
  for (auto& b : blend)
    b.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = static_cast<uint32_t>(blend.size());
  cb.pAttachments = blend.data();
  // Locations keep their numbers: an unused one is VK_FORMAT_UNDEFINED (no attachment).
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = static_cast<uint32_t>(d.colour_formats.size());
  rendering.pColorAttachmentFormats = d.colour_formats.data();
  rendering.depthAttachmentFormat = d.depth != DepthUse::none ? kDepthFormat : VK_FORMAT_UNDEFINED;

  const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;

  VkGraphicsPipelineCreateInfo gci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  gci.pNext = &rendering;
  gci.flags = d.flags;
  gci.stageCount = 2;
  gci.pStages = stages;
  gci.pVertexInputState = &vi;
  gci.pInputAssemblyState = &ia;
  gci.pViewportState = &vp;
  gci.pRasterizationState = &rs;
  gci.pMultisampleState = &ms;
  gci.pDepthStencilState = &ds;
  gci.pColorBlendState = &cb;
  gci.layout = d.layout;
  if (d.dynamic_viewport) gci.pDynamicState = &dynamic;
  return vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &gci, nullptr, pipeline);
}

}  // namespace aovar::render::vk
