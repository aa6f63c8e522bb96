#include "render/gbuffer_share.h"

#include <algorithm>
#include <atomic>
#include <cstring>

#include <fmt/format.h>

#include "util/hash.h"

namespace aovar::render {

std::uint64_t next_scene_generation() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

bool GbufferContent::operator==(const GbufferContent& o) const {
  // Bitwise: a G-buffer is reused only for the very same camera, never for one that compares equal as floats.
  return scene == o.scene && std::memcmp(&view, &o.view, sizeof view) == 0 &&
         std::memcmp(&proj, &o.proj, sizeof proj) == 0 && std::memcmp(&clip, &o.clip, sizeof clip) == 0;
}

GbufferContent gbuffer_content(const FrameBlock& block, std::uint64_t scene_generation) {
  return GbufferContent{scene_generation, block.view, block.proj, glm::vec2(block.clip.x, block.clip.y)};
}

namespace {

// Everything that decides what the G-buffer plan draws: its programs' code, the targets' formats and clears,
// its parameter block, the frame size. Two plans with equal keys draw bit-identical G-buffers.
std::string split_key(const PipelinePlan& g, Extent size) {
  util::Hasher h;
  h.add(std::uint64_t(size.width)).add(std::uint64_t(size.height));
  for (const Shader& s : g.shaders) {
    h.add(s.program_key).add(std::uint64_t(s.stage)).add(s.glsl);
    h.add(std::string_view(reinterpret_cast<const char*>(s.spirv.data()), s.spirv.size() * sizeof(std::uint32_t)));
  }
  for (const Texture& t : g.textures) {
    h.add(std::uint64_t(t.format)).add(std::uint64_t(t.cleared)).add(std::uint64_t(t.levels));
    h.add(std::string_view(reinterpret_cast<const char*>(t.clear.data()), sizeof t.clear));
  }
  const Draw& d = g.draws.front();
  for (const TextureRef& o : d.outputs) h.add(std::uint64_t(o.texture + 1));
  h.add(std::string_view(reinterpret_cast<const char*>(d.params.data()), d.params.size() * sizeof(float)));
  return h.hex();
}

// Whether some draw other than `geometry` writes texture `t` or depth buffer `z` of `plan`.
bool written_elsewhere(const PipelinePlan& plan, std::size_t geometry, int t, int z) {
  for (std::size_t i = 0; i < plan.draws.size(); ++i) {
    if (i == geometry) continue;
    const Draw& d = plan.draws[i];
    if (z >= 0 && d.depth_buffer == z && d.depth != DepthUse::skip_background) return true;
    for (const TextureRef& o : d.outputs)
      if (t >= 0 && o.texture == t) return true;
  }
  return false;
}

}  // namespace

std::optional<GbufferSplit> split_gbuffer(const PipelinePlan& plan, Extent size) {
  const auto geometry = std::count_if(plan.draws.begin(), plan.draws.end(), [](const Draw& d) { return d.geometry; });
  if (geometry != 1) return std::nullopt;
  GbufferSplit s;
  s.draw = static_cast<std::size_t>(
      std::find_if(plan.draws.begin(), plan.draws.end(), [](const Draw& d) { return d.geometry; }) - plan.draws.begin());
  const Draw& source = plan.draws[s.draw];
  if (source.depth_buffer < 0 || written_elsewhere(plan, s.draw, -1, source.depth_buffer)) return std::nullopt;
  s.depth_buffer = source.depth_buffer;
  s.texture.assign(plan.textures.size(), -1);

  PipelinePlan& g = s.gbuffer;
  g.variant = "G-buffer";
  g.depth_buffers = {plan.depth_buffers[source.depth_buffer]};
  Draw d = source;
  d.depth_buffer = 0;
  for (TextureRef& o : d.outputs) {
    if (o.texture < 0) continue;
    const Texture& t = plan.textures[o.texture];
    if (t.double_buffered || written_elsewhere(plan, s.draw, o.texture, -1)) return std::nullopt;
    s.texture[o.texture] = static_cast<int>(g.textures.size());
    g.variant += " " + std::string(format_name(t.format));
    g.textures.push_back(t);
    o.texture = s.texture[o.texture];
  }
  g.shaders = {plan.shaders.at(source.vertex), plan.shaders.at(source.fragment)};
  d.vertex = 0;
  d.fragment = 1;
  g.draws = {std::move(d)};
  g.result = -1;  // nothing reads a G-buffer back: the variants sample it
  s.key = split_key(g, size);
  return s;
}

std::shared_ptr<SharedGbuffer> GbufferPool::get(const GbufferSplit& split, Extent size, const Prepare& prepare) {
  if (size.width != kept_size_.width || size.height != kept_size_.height) {
    kept_.clear();  // a run at another size: the old ones live on only while their pipelines do
    kept_size_ = size;
    std::erase_if(by_key_, [](const auto& entry) { return entry.second.expired(); });
  }
  if (auto alive = by_key_[split.key].lock()) return alive;
  auto shared = std::make_shared<SharedGbuffer>();
  shared->pipeline = prepare(split.gbuffer);
  by_key_[split.key] = shared;
  kept_.push_back(shared);
  return shared;
}

double GbufferPool::ensure(SharedGbuffer& g, const GbufferContent& content, bool force, const Draw& draw) {
  if (!force && g.holds && *g.holds == content) return g.last_ms;
  g.holds.reset();  // a draw that throws leaves it holding nothing known
  const std::vector<double> ms = draw(*g.pipeline);
  g.last_ms = ms.empty() ? 0.0 : ms.front();
  g.holds = content;
  return g.last_ms;
}

}  // namespace aovar::render
