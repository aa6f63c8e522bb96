#include "pipeline.h"

#include "formats.h"
#include "vk_util.h"

namespace render_variant {
namespace {

// The plan's depth uses (docs/template-contract.md, Draw::depth): write_mask writes the fullscreen triangle's 1.0
// wherever the shader does not discard; skip_background rejects pixels whose depth holds that 1.0 (background).
VkPipelineDepthStencilStateCreateInfo depth_state(shaders::DepthUse use) {
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = use != shaders::DepthUse::none;
  ds.depthWriteEnable = use == shaders::DepthUse::geometry || use == shaders::DepthUse::write_mask;
  ds.depthCompareOp = use == shaders::DepthUse::write_mask        ? VK_COMPARE_OP_ALWAYS
                      : use == shaders::DepthUse::skip_background ? VK_COMPARE_OP_NOT_EQUAL
                                                                  : VK_COMPARE_OP_LESS;
  return ds;
}

}  // namespace

VkPipeline create_pipeline(VkDevice device, const PipelineDesc& d) {
  VkPipelineShaderStageCreateInfo stages[2]{};
  const VkShaderStageFlagBits kinds[2] = {VK_SHADER_STAGE_VERTEX_BIT, VK_SHADER_STAGE_FRAGMENT_BIT};
  const VkShaderModule modules[2] = {d.vertex, d.fragment};
  for (int i = 0; i < 2; ++i)
    stages[i] = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, kinds[i], modules[i], "main"};
  // The fullscreen triangle comes from gl_VertexIndex: no vertex buffers.
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkViewport viewport{0, 0, float(d.extent.width), float(d.extent.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, d.extent};
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = vp.scissorCount = 1;
  vp.pViewports = &viewport;
  vp.pScissors = &scissor;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;  // the fullscreen triangle's winding depends on the API's y direction
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  const VkPipelineDepthStencilStateCreateInfo ds = depth_state(d.depth);
  std::vector<VkPipelineColorBlendAttachmentState> blend(d.colour_formats.size());
  for (auto& b : blend)
    b.colorWriteMask =
        VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = static_cast<uint32_t>(blend.size());
  cb.pAttachments = blend.data();
  // Output locations keep their numbers: an unused one has VK_FORMAT_UNDEFINED (no attachment).
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = static_cast<uint32_t>(d.colour_formats.size());
  rendering.pColorAttachmentFormats = d.colour_formats.data();
  rendering.depthAttachmentFormat = d.depth != shaders::DepthUse::none ? kDepthFormat : VK_FORMAT_UNDEFINED;

  VkGraphicsPipelineCreateInfo gci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  gci.pNext = &rendering;
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
  VkPipeline pipeline = VK_NULL_HANDLE;
  check(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &gci, nullptr, &pipeline), "vkCreateGraphicsPipelines");
  return pipeline;
}

}  // namespace render_variant
