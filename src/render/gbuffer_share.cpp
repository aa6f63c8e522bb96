#include "render/gbuffer_share.h"

#include <algorithm>
#include <atomic>
#include <cmath>
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
  shared->key = split.key;
  shared->planes = gbuffer_planes(split.gbuffer);
  shared->size = size;
  by_key_[split.key] = shared;
  kept_.push_back(shared);
  return shared;
}

double GbufferPool::ensure(SharedGbuffer& g, const GbufferContent& content, const FrameBlock& frame, bool force,
                           const GbufferOps& ops, const GbufferStore* store) {
  if (!force && g.holds && *g.holds == content) return g.last_ms;
  g.holds.reset();  // a draw or upload that throws leaves it holding nothing known
  // A forced draw (a timed round) neither reads nor fills the store: the stills keep it.
  const bool stores = !force && store && store->enabled() && ops.read && ops.upload;
  const std::string key = stores ? store->key(g, content) : "";
  if (stores) {
    if (auto planes = store->load(key, g)) {
      ops.upload(*g.pipeline, *planes);
      ++loads_;
      g.holds = content;
      return g.last_ms;
    }
  }
  const std::vector<double> ms = ops.draw(*g.pipeline);
  g.last_ms = ms.empty() ? 0.0 : ms.front();
  g.holds = content;
  if (stores) store->save(key, g, frame, ops.read(*g.pipeline));  // a still's first draw: keep it
  return g.last_ms;
}

std::vector<std::pair<std::string, std::string>> gbuffer_planes(const PipelinePlan& gbuffer) {
  std::vector<std::pair<std::string, std::string>> planes;
  for (const TextureRef& o : gbuffer.draws.front().outputs)
    if (o.texture >= 0) planes.emplace_back(gbuffer.textures[o.texture].name, format_name(gbuffer.textures[o.texture].format));
  planes.emplace_back("zbuffer", "d32f");
  return planes;
}

GbufferStore::GbufferStore(std::filesystem::path cache_dir, std::string device)
    : cache_(std::move(cache_dir), "gbuffer"), device_(std::move(device)) {}

void GbufferStore::set_scene(std::uint64_t generation, std::string content_hash) {
  scenes_[generation] = std::move(content_hash);
}

std::string GbufferStore::key(const SharedGbuffer& g, const GbufferContent& c) const {
  const auto scene = scenes_.find(c.scene);
  // A scene this store was not told about has no content to key by: a key no entry has, so nothing is shared.
  const std::string scene_hash = scene == scenes_.end() ? fmt::format("generation {}", c.scene) : scene->second;
  auto bytes = [](const auto& v) { return std::string_view(reinterpret_cast<const char*>(&v), sizeof v); };
  util::Hasher h;
  h.add(device_).add(scene_hash).add(g.key).add(bytes(c.view)).add(bytes(c.proj)).add(bytes(c.clip));
  return fmt::format("gbuffer 1 {}", h.hex());
}

namespace {

// Why stored planes cannot stand for G-buffer `g` ("" when they can): the planes its plan's draw writes and its
// depth buffer, in that order, with their formats, at its size, every float finite (the draw writes no other).
std::string unfit(const std::vector<GbufferPlane>& planes, const SharedGbuffer& g, Extent size) {
  const auto& want = g.planes;
  if (planes.size() != want.size()) return fmt::format("{} planes, not {}", planes.size(), want.size());
  if (size.width != g.size.width || size.height != g.size.height) return "another frame size";
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const GbufferPlane& p = planes[i];
    if (p.name != want[i].first || p.format != want[i].second) return fmt::format("plane {} is not {}", i, want[i].first);
    if (p.format == "rgba8" || p.format == "rg8") continue;
    for (std::size_t at = 0; at < p.texels.size(); at += p.format == "r16f" ? 2 : 4) {
      if (p.format == "r16f") {
        const unsigned hi = static_cast<unsigned char>(p.texels[at + 1]);
        if ((hi & 0x7c) == 0x7c) return fmt::format("plane {} holds a non-finite half", p.name);  // exponent all ones
        continue;
      }
      float v;
      std::memcpy(&v, p.texels.data() + at, sizeof v);
      if (!std::isfinite(v)) return fmt::format("plane {} holds a non-finite float", p.name);
    }
  }
  return "";
}

}  // namespace

std::optional<std::vector<GbufferPlane>> GbufferStore::load(const std::string& key, const SharedGbuffer& g) const {
  const std::optional<std::string> bytes = cache_.read(key);
  if (!bytes) return std::nullopt;
  try {
    GbufferImage image = decode_gbuffer(*bytes, "the entry");
    if (const std::string why = unfit(image.planes, g, image.size); !why.empty()) {
      cache_.reject(key, why);
      return std::nullopt;
    }
    return std::move(image.planes);
  } catch (const std::runtime_error& e) {
    cache_.reject(key, e.what());
    return std::nullopt;
  }
}

void GbufferStore::save(const std::string& key, const SharedGbuffer& g, const FrameBlock& frame,
                        std::vector<GbufferPlane> planes) const {
  cache_.write(key, encode_gbuffer(GbufferImage{g.size, frame, std::move(planes)}));
}

}  // namespace aovar::render
