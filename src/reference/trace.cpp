// Embree scene, camera rays and hemisphere integration of the reference (see reference.h and docs/architecture.md, "Ground truth and error").
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "reference/detail.h"
#include "reference/sampling.h"

namespace aovar::reference::detail {

std::atomic<std::uint64_t> trace_calls{0};

namespace {

using Clock = std::chrono::steady_clock;

// The first error Embree reports on a device, kept for the exception.
struct DeviceErrors {
  RTCError code = RTC_ERROR_NONE;
  std::string message;
};

void on_device_error(void* user, RTCError code, const char* message) {
  auto* e = static_cast<DeviceErrors*>(user);
  if (e->code == RTC_ERROR_NONE) {
    e->code = code;
    e->message = message ? message : "";
  }
}

// RAII over an Embree device and one committed scene holding every triangle of a scene::Scene.
class EmbreeScene {
 public:
  explicit EmbreeScene(const scene::Scene& sc) {
    device_ = rtcNewDevice(nullptr);
    if (!device_)
      throw std::runtime_error(fmt::format("Embree: cannot create a device ({}): check libembree3 is installed (scripts/deps)",
                                           static_cast<int>(rtcGetDeviceError(nullptr))));
    rtcSetDeviceErrorFunction(device_, on_device_error, &errors_);
    scene_ = rtcNewScene(device_);
    // Robust: watertight traversal, no precision-reducing shortcuts; high quality: spatial splits (the
    // build costs well under a second for 10^5 triangles, tracing dominates).
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    const std::size_t vertices = sc.positions.size(), triangles = sc.triangle_count();
    // Copied into Embree-owned buffers: a shared float3 buffer would need padding after its last element.
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices));
    auto* t = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), triangles));
    if (!v || !t) {
      rtcReleaseGeometry(geom);
      check("allocating the geometry buffers");
    }
    for (std::size_t i = 0; i < vertices; ++i) {
      v[3 * i] = sc.positions[i].x, v[3 * i + 1] = sc.positions[i].y, v[3 * i + 2] = sc.positions[i].z;
    }
    std::copy(sc.indices.begin(), sc.indices.begin() + static_cast<std::ptrdiff_t>(3 * triangles), t);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
    check("building the BVH");
  }
  ~EmbreeScene() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene scene() const { return scene_; }
  void check(const char* what) const {
    if (errors_.code != RTC_ERROR_NONE)
      throw std::runtime_error(fmt::format("Embree: error {} while {}: {}", static_cast<int>(errors_.code), what,
                                           errors_.message));
  }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  DeviceErrors errors_;
};

// The rasteriser's camera for one view and frame: eye, view-to-world rotation and the projection offsets.
// Directions are built with view-space z = -1, so a ray's t is its depth along the view axis, the quantity
// the rasteriser clips at near and far.
struct Camera {
  glm::vec3 eye;
  glm::mat3 to_world;
  glm::vec4 proj_info;
  float near_plane, far_plane;
  int width, height;

  glm::vec3 direction(int x, int y) const {
    glm::vec2 ndc{(static_cast<float>(x) + 0.5f) / static_cast<float>(width) * 2.0f - 1.0f,
                  (static_cast<float>(y) + 0.5f) / static_cast<float>(height) * 2.0f - 1.0f};  // row 0: ndc y = -1
    glm::vec3 d{ndc.x * proj_info.x + proj_info.z, ndc.y * proj_info.y + proj_info.w, -1.0f};
    return to_world * d;
  }
};

Camera make_camera(const scene::View& view, const ReferenceOptions& o) {
  render::FrameSetup setup;
  setup.view = &view;
  setup.frame = o.frame;
  setup.static_camera = false;  // pose of path frame (frame mod path_frames), as `measure --camera-path` renders it
  setup.radius = o.radius;
  render::FrameBlock b = render::make_frame_block(setup, o.size, o.size, render::ClipDepth::zero_to_one);
  glm::mat4 inv_view = glm::inverse(b.view);
  Camera c;
  c.eye = glm::vec3(inv_view[3]);
  c.to_world = glm::mat3(inv_view);
  c.proj_info = b.proj_info;
  c.near_plane = b.clip.x;
  c.far_plane = b.clip.y;
  c.width = o.size.width;
  c.height = o.size.height;
  return c;
}

// Result of one pixel.
struct PixelResult {
  float visibility = 1.0f, std_error = 0.0f;
  float depth = std::numeric_limits<float>::infinity();  // linear view depth of the primary hit
  bool background = true;
  std::uint32_t rays = 1;
};

constexpr float kInf = std::numeric_limits<float>::infinity();

void set_ray(RTCRay& ray, glm::vec3 org, glm::vec3 dir, float tnear, float tfar) {
  ray.org_x = org.x, ray.org_y = org.y, ray.org_z = org.z;
  ray.dir_x = dir.x, ray.dir_y = dir.y, ray.dir_z = dir.z;
  ray.tnear = tnear;
  ray.tfar = tfar;
  ray.time = 0.0f;
  ray.mask = 0xffffffffu;
  ray.id = 0;
  ray.flags = 0;
}


class PixelTracer {
 public:
  PixelTracer(RTCScene scene, const Camera& cam, const ReferenceOptions& o, RayApi api, float scene_diagonal)
      : scene_(scene), cam_(cam), o_(o), api_(api), diagonal_(scene_diagonal) {
    // The sample set is the same for every pixel (only its rotation differs): compute it once.
    points_.resize(static_cast<std::size_t>(o.rays));
    for (int i = 0; i < o.rays; ++i) points_[static_cast<std::size_t>(i)] = sobol2(static_cast<std::uint32_t>(i));
  }

  PixelResult trace(int x, int y) const {
    PixelResult r;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    glm::vec3 dir = cam_.direction(x, y);
    RTCRayHit rh{};
    set_ray(rh.ray, cam_.eye, dir, cam_.near_plane, background_depth());
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return r;
    r.background = false;

    const float t = rh.ray.tfar;
    r.depth = t;  // view-space z = -1: t is the linear depth, as trace_depth's
    glm::vec3 p = cam_.eye + t * dir;
    glm::vec3 n = glm::normalize(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    if (glm::dot(n, dir) > 0.0f) n = -n;  // face the camera: AO of the side we see
    // Self-intersection offset. P carries the rounding of its coordinates (|P| * 2^-24 each) and of
    // Embree's hit distance (a few ulps of t |d|): 2e-5 of the larger of the two is about 300 ulps, far
    // above both, and far below any radius worth asking for (a 1e-3 bias on a radius 50x larger than the
    // offset changes visibility by about 1e-4). The floor 1e-7 of the scene's diagonal covers points at the origin.
    float scale = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), t * glm::length(dir)});
    float eps = std::max(2e-5f * scale, 1e-7f * diagonal_);
    glm::vec3 origin = p + eps * n;
    glm::vec3 tu, tv;
    tangent_frame(n, tu, tv);
    glm::vec2 shift = pixel_shift(x, y);

    // Per-ray occlusion o_i in [0, 1]; visibility = 1 - mean.
    double sum = 0, sum_sq = 0;
    const int count = o_.rays;
    auto direction = [&](int i) {
      glm::vec3 l = malley(rotate(points_[static_cast<std::size_t>(i)], shift));
      return l.x * tu + l.y * tv + l.z * n;
    };
    const bool obscurance = o_.mode == Mode::obscurance;
    if (api_ == RayApi::single) {
      for (int i = 0; i < count; ++i) {
        double occ = 0;
        if (obscurance) {
          RTCRayHit h{};
          set_ray(h.ray, origin, direction(i), 0.0f, o_.radius);
          h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(scene_, &ctx, &h);
          if (h.hit.geomID != RTC_INVALID_GEOMETRY_ID) occ = 1.0 - static_cast<double>(h.ray.tfar) / o_.radius;
        } else {
          RTCRay ray{};
          set_ray(ray, origin, direction(i), 0.0f, o_.radius);
          rtcOccluded1(scene_, &ctx, &ray);
          if (ray.tfar == -kInf) occ = 1.0;
        }
        sum += occ;
        sum_sq += occ * occ;
      }
    } else {
      alignas(32) int valid[8];
      for (int base = 0; base < count; base += 8) {
        const int lanes = std::min(8, count - base);
        for (int j = 0; j < 8; ++j) valid[j] = j < lanes ? -1 : 0;
        if (obscurance) {
          alignas(32) RTCRayHit8 h;
          fill_packet(h.ray, lanes, origin, base, direction);
          for (int j = 0; j < 8; ++j) h.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect8(valid, scene_, &ctx, &h);
          for (int j = 0; j < lanes; ++j)
            if (h.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID) {
              double occ = 1.0 - static_cast<double>(h.ray.tfar[j]) / o_.radius;
              sum += occ;
              sum_sq += occ * occ;
            }
        } else {
          alignas(32) RTCRay8 ray;
          fill_packet(ray, lanes, origin, base, direction);
          rtcOccluded8(valid, scene_, &ctx, &ray);
          for (int j = 0; j < lanes; ++j)
            if (ray.tfar[j] == -kInf) sum += 1.0, sum_sq += 1.0;
        }
      }
    }
    const double mean = sum / count;
    r.visibility = static_cast<float>(1.0 - mean);
    // Standard error of the mean from the sample variance, as if the rays were independent. For a
    // (rotated) low-discrepancy set the true error is smaller, so this is conservative. One ray has no
    // sample variance: report 0.5, the largest standard deviation of a value in [0, 1].
    if (count > 1) {
      double var = std::max(0.0, (sum_sq - sum * mean) / (count - 1));
      r.std_error = static_cast<float>(std::sqrt(var / count));
    } else {
      r.std_error = 0.5f;
    }
    r.rays += static_cast<std::uint32_t>(count);
    return r;
  }

 private:
  // Surfaces at or beyond 0.999 far are background to every AO method (ao_is_background in
  // shader_src/common/depth.glsl), and the rasteriser clips at near: the primary ray covers that range.
  float background_depth() const { return cam_.far_plane * 0.999f; }

  template <class Dir>
  void fill_packet(RTCRay8& ray, int lanes, glm::vec3 origin, int base, const Dir& direction) const {
    for (int j = 0; j < 8; ++j) {
      glm::vec3 d = j < lanes ? direction(base + j) : glm::vec3(0.0f, 0.0f, 1.0f);
      ray.org_x[j] = origin.x, ray.org_y[j] = origin.y, ray.org_z[j] = origin.z;
      ray.dir_x[j] = d.x, ray.dir_y[j] = d.y, ray.dir_z[j] = d.z;
      ray.tnear[j] = 0.0f;
      ray.tfar[j] = o_.radius;
      ray.time[j] = 0.0f;
      ray.mask[j] = 0xffffffffu;
      ray.id[j] = static_cast<unsigned>(j);
      ray.flags[j] = 0;
    }
  }

  RTCScene scene_;
  const Camera& cam_;
  const ReferenceOptions& o_;
  RayApi api_;
  float diagonal_;
  std::vector<glm::vec2> points_;
};

}  // namespace

ReferenceImage trace(const scene::Scene& sc, const scene::View& view, const ReferenceOptions& o,
                     const Progress& progress, RayApi api) {
  ++trace_calls;
  const auto start = Clock::now();
  const int w = o.size.width, h = o.size.height;
  ReferenceImage out;
  out.visibility = {w, h, std::vector<float>(static_cast<std::size_t>(w) * h, 1.0f)};
  out.std_error = {w, h, std::vector<float>(static_cast<std::size_t>(w) * h, 0.0f)};
  out.background.assign(static_cast<std::size_t>(w) * h, 1);
  out.depth = {w, h, std::vector<float>(static_cast<std::size_t>(w) * h, kInf)};

  // Threads: `threads` caps TBB process-wide while we run (Embree's BVH build runs on TBB too) and sizes
  // the arena the work runs in. Alone: an arena of one (no worker slot) and no cap.
  const int threads = o.alone ? 1 : o.threads > 0 ? o.threads : tbb::this_task_arena::max_concurrency();
  std::unique_ptr<tbb::global_control> cap;
  if (o.threads > 0 && !o.alone)
    cap = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                static_cast<std::size_t>(threads));
  tbb::task_arena arena(threads);

  // Tiles of 16 x 8 pixels: neighbouring primary rays share BVH nodes; enough tiles to balance 2-64 threads.
  constexpr int kTileW = 16, kTileH = 8;
  const int tiles_x = (w + kTileW - 1) / kTileW, tiles_y = (h + kTileH - 1) / kTileH;
  const int tiles = tiles_x * tiles_y;
  std::atomic<std::int64_t> pixels_done{0};
  std::atomic<std::uint64_t> rays{0};
  std::atomic<bool> cancel{false};

  auto work = [&] {
    EmbreeScene embree(sc);
    Camera cam = make_camera(view, o);
    PixelTracer tracer(embree.scene(), cam, o, api, sc.bounds.diagonal());
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& range) {
      std::uint64_t tile_rays = 0;
      for (int tile = range.begin(); tile < range.end(); ++tile) {
        if (cancel.load(std::memory_order_relaxed)) return;
        const int x0 = (tile % tiles_x) * kTileW, y0 = (tile / tiles_x) * kTileH;
        const int x1 = std::min(w, x0 + kTileW), y1 = std::min(h, y0 + kTileH);
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) {
            PixelResult p = tracer.trace(x, y);
            const std::size_t i = static_cast<std::size_t>(y) * w + x;
            out.visibility.pixels[i] = p.visibility;
            out.std_error.pixels[i] = p.std_error;
            out.background[i] = p.background ? 1 : 0;
            out.depth.pixels[i] = p.depth;
            tile_rays += p.rays;
          }
        pixels_done.fetch_add(static_cast<std::int64_t>(x1 - x0) * (y1 - y0), std::memory_order_relaxed);
      }
      rays.fetch_add(tile_rays, std::memory_order_relaxed);
    });
    embree.check("tracing");
  };

  const double total = static_cast<double>(w) * h;
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  if (!progress) {
    arena.execute(work);
  } else {
    // The work runs on its own thread (joining the arena as its master); this thread only reports
    // progress, so the callback never runs on a worker.
    auto done = std::async(std::launch::async, [&] { arena.execute(work); });
    progress(0.0, seconds());
    while (done.wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
      try {
        progress(static_cast<double>(pixels_done.load()) / total, seconds());
      } catch (...) {
        cancel = true;  // the caller gave up: stop the workers, then pass its exception on
        done.wait();
        throw;
      }
    }
    done.get();  // rethrows a worker's exception
    progress(1.0, seconds());
  }
  out.trace_s = seconds();
  out.rays_traced = rays.load();
  return out;
}

}  // namespace aovar::reference::detail

namespace aovar::reference {

DepthImage trace_depth(const scene::Scene& sc, const scene::View& view, render::Extent size, int frame, int threads) {
  if (size.width < 1 || size.height < 1) throw std::runtime_error("trace_depth: empty size");
  ReferenceOptions o;
  o.size = size;
  o.frame = frame;
  o.radius = 1.0f;
  const int w = size.width, h = size.height;
  DepthImage out;
  out.depth = {w, h, std::vector<float>(static_cast<std::size_t>(w) * h, detail::kInf)};
  out.normal.assign(out.depth.pixels.size(), glm::vec3(0.0f));
  out.shading_normal.assign(out.depth.pixels.size(), glm::vec3(0.0f));
  const int n = threads > 0 ? threads : tbb::this_task_arena::max_concurrency();
  std::unique_ptr<tbb::global_control> cap;
  if (threads > 0)
    cap = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(n));
  tbb::task_arena arena(n);
  arena.execute([&] {
    detail::EmbreeScene embree(sc);
    const detail::Camera cam = detail::make_camera(view, o);
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      for (int y = rows.begin(); y < rows.end(); ++y)
        for (int x = 0; x < w; ++x) {
          const glm::vec3 dir = cam.direction(x, y);  // view-space z = -1: t is the linear depth
          RTCRayHit rh{};
          detail::set_ray(rh.ray, cam.eye, dir, cam.near_plane, cam.far_plane * 0.999f);
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(embree.scene(), &ctx, &rh);
          if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
          const std::size_t i = static_cast<std::size_t>(y) * w + x;
          out.depth.pixels[i] = rh.ray.tfar;
          glm::vec3 ng = glm::normalize(glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
          out.normal[i] = glm::dot(ng, dir) > 0.0f ? -ng : ng;
          if (!sc.normals.empty()) {  // Embree's (u, v) weigh the triangle's second and third vertex
            const std::uint32_t* tri = &sc.indices[3 * static_cast<std::size_t>(rh.hit.primID)];
            const glm::vec3 s = (1.0f - rh.hit.u - rh.hit.v) * sc.normals[tri[0]] + rh.hit.u * sc.normals[tri[1]] +
                                rh.hit.v * sc.normals[tri[2]];
            if (glm::dot(s, s) > 0.0f) out.shading_normal[i] = glm::normalize(s);
          }
        }
    });
    embree.check("tracing depth");
  });
  return out;
}

}  // namespace aovar::reference
