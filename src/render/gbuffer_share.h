#pragma once
// One G-buffer per frame size and format, shared by every prepared pipeline that draws it alike, as a render
// graph shares a resource by its description (Unreal's RDG, Unity's render graph): variants differ in their AO
// passes, not in the scene's raster, which on a large scene is nearly all of a frame (bench/scene_scale). A backend prepares the G-buffer draw once
// per key (GbufferSplit::key: programs, formats, clears, size), lends its textures and depth buffer to the
// pipelines, and draws it only when a frame needs other content than it holds (GbufferContent). Both backends
// use this file; the images and names they lend are their own.
//
// The contract that makes this exact (docs/template-contract.md): the gbuffer pass's output depends only on
// the scene, AOFrame's view, proj and clip.xy, and its own parameters, never on ao_size, clip.zw or frame_index.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "render/backend.h"
#include "render/frame.h"
#include "render/gbuffer_file.h"
#include "render/plan.h"
#include "util/verified_cache.h"

namespace aovar::render {

// A new identity for a scene upload, unique in the process (every backend's set_scene() takes one): a recorded
// frame and a shared G-buffer name the scene they drew.
std::uint64_t next_scene_generation();

// What a G-buffer holds: the scene upload it drew, and the frame block members its shaders read. Two frames
// with equal content draw bit-identical G-buffers.
struct GbufferContent {
  std::uint64_t scene = 0;  // the backend's scene generation (each set_scene() a new one)
  glm::mat4 view{1.0f}, proj{1.0f};
  glm::vec2 clip{0.0f};     // AOFrame's clip.xy: near plane, background depth (what the targets clear to);
                            // clip.zw (radius, pixel scale of the AO extent) differ between variants
  bool operator==(const GbufferContent& o) const;
};
GbufferContent gbuffer_content(const FrameBlock& block, std::uint64_t scene_generation);

// A variant's plan (at the size it runs, plan_for_size) split into its G-buffer draw and the rest.
struct GbufferSplit {
  PipelinePlan gbuffer;        // the geometry draw alone, its output textures and depth buffer; result -1
  std::string key;             // pipelines whose splits have equal keys share one G-buffer
  std::size_t draw = 0;        // the geometry draw's index in the variant's plan
  std::vector<int> texture;    // per texture of the variant's plan: its index in `gbuffer`, -1 if not the G-buffer's
  int depth_buffer = -1;       // the variant's depth buffer that is the G-buffer's (depth buffer 0 of `gbuffer`)
};

// The split of `plan`, or nothing when it cannot share: not exactly one geometry draw, or a later draw that
// writes one of its textures or its depth buffer (then the G-buffer is not the geometry draw's alone).
std::optional<GbufferSplit> split_gbuffer(const PipelinePlan& plan, Extent size);

// (name, format) of the planes a G-buffer plan's draw leaves, in G-buffer file order: its outputs, then
// "zbuffer" (d32f), as Backend::read_gbuffer returns them.
std::vector<std::pair<std::string, std::string>> gbuffer_planes(const PipelinePlan& gbuffer);

// A prepared G-buffer and what it holds now.
struct SharedGbuffer {
  std::unique_ptr<PreparedPipeline> pipeline;  // prepared from GbufferSplit::gbuffer
  std::string key;                             // GbufferSplit::key
  // What a stored copy must hold: (name, format) of each plane, in file order (gbuffer_planes).
  std::vector<std::pair<std::string, std::string>> planes;
  Extent size;
  std::optional<GbufferContent> holds;         // nothing before its first draw
  double last_ms = 0;                          // its draw's time when last drawn (0: never drawn, only loaded)
};

// G-buffers kept across runs in the verified cache (kind "gbuffer", util/verified_cache.h), as the reference is:
// an entry is a G-buffer file (gbuffer_file.h) keyed by the backend's device, the scene's content, the camera
// (view, proj, clip.xy) and the split's key (programs, formats, clears, size). A still of a later run on the
// same inputs uploads it instead of rasterising the scene; an entry whose planes do not fit the G-buffer (names,
// formats, size) or hold non-finite floats is recomputed with a warning. Timed rounds always draw.
class GbufferStore {
 public:
  GbufferStore(std::filesystem::path cache_dir, std::string device);
  bool enabled() const { return cache_.enabled(); }
  // The scene an upload generation stands for, by its content hash (scene::Scene::content_hash).
  void set_scene(std::uint64_t generation, std::string content_hash);
  std::string key(const SharedGbuffer& g, const GbufferContent& content) const;
  std::optional<std::vector<GbufferPlane>> load(const std::string& key, const SharedGbuffer& g) const;
  void save(const std::string& key, const SharedGbuffer& g, const FrameBlock& frame,
            std::vector<GbufferPlane> planes) const;

 private:
  util::VerifiedCache cache_;
  std::string device_;
  std::map<std::uint64_t, std::string> scenes_;
};

// What a backend does to a shared G-buffer: draw it (its time per draw), and with a store read it back and upload
// a stored copy (null where the backend cannot: the GL backends draw every time).
struct GbufferOps {
  std::function<std::vector<double>(PreparedPipeline&)> draw;
  std::function<std::vector<GbufferPlane>(PreparedPipeline&)> read;
  std::function<void(PreparedPipeline&, const std::vector<GbufferPlane>&)> upload;
};

// The shared G-buffers of one backend. Keeps those of the latest frame size alive between batches, so a run
// draws each format once per view (and again only when the camera moves); others live while a pipeline uses them.
class GbufferPool {
 public:
  using Prepare = std::function<std::unique_ptr<PreparedPipeline>(const PipelinePlan&)>;

  // The G-buffer for `split`, prepared with `prepare` the first time its key is asked for at this size.
  std::shared_ptr<SharedGbuffer> get(const GbufferSplit& split, Extent size, const Prepare& prepare);

  // Makes `g` hold `content` when it holds other content (always with `force`): uploads the store's copy when
  // there is one and nothing forces a draw, else draws it (and stores what it drew). `frame` is the frame block
  // a stored file carries. Returns its draw's time (last_ms).
  double ensure(SharedGbuffer& g, const GbufferContent& content, const FrameBlock& frame, bool force,
                const GbufferOps& ops, const GbufferStore* store = nullptr);
  std::size_t loads() const { return loads_; }  // G-buffers uploaded from the store instead of drawn

 private:
  std::map<std::string, std::weak_ptr<SharedGbuffer>> by_key_;
  std::vector<std::shared_ptr<SharedGbuffer>> kept_;  // those of kept_size_
  Extent kept_size_{};
  std::size_t loads_ = 0;
};

}  // namespace aovar::render
