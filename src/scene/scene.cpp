// Scene loading entry point (dispatch by spec), camera paths, view lookup and the helpers every loader
// shares: one-line errors, memory limits, normals, bounds and the content hash.
#include "scene/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include "scene/detail.h"
#include "scene/tessellate.h"
#include "util/fs.h"
#include "util/hash.h"
#include "util/text.h"

namespace aovar::scene {
namespace fs = std::filesystem;

static_assert(sizeof(glm::vec3) == 12, "positions and normals are hashed and uploaded as packed floats");

namespace detail {

void fail(std::string_view message) { throw SceneError(util::one_line(message)); }

std::string format_bytes(std::uint64_t bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 4) v /= 1024.0, ++u;
  return u == 0 ? fmt::format("{} bytes", bytes) : fmt::format("{:.1f} {}", v, units[u]);
}

std::uint64_t memory_limit(const LoadOptions& options) {
  if (options.memory_limit) return options.memory_limit;
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024 / 2;
  long pages = ::sysconf(_SC_AVPHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0) return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) / 2;
  return std::uint64_t{4} << 30;  // unknown: assume a modest machine
}

void check_memory(const std::string& display, std::uint64_t estimate, std::uint64_t limit, std::string_view what) {
  if (estimate <= limit) return;
  fail(
      fmt::format("{}: error: scene too large: needs about {} in memory ({}), limit {} (use a smaller or "
                  "decimated scene, or free memory: the limit is half of the available memory)",
                  display, format_bytes(estimate), what, format_bytes(limit)));
}

std::uint64_t scene_bytes(std::uint64_t vertices, std::uint64_t indices) {
  return vertices * 2 * sizeof(glm::vec3) + indices * sizeof(std::uint32_t);
}

void check_size(const std::string& display, std::uint64_t vertices, std::uint64_t indices, const LoadOptions& options) {
  if (indices / 3 > kMaxTriangles || vertices >= 0xffffffffu)
    fail(
        fmt::format("{}: error: {} triangles and {} vertices is more than aovar handles (at most {} triangles; "
                    "decimate the mesh)",
                    display, indices / 3, vertices, kMaxTriangles));
  check_memory(display, scene_bytes(vertices, indices), memory_limit(options),
               fmt::format("{} vertices, {} triangles", vertices, indices / 3));
}

glm::vec3 safe_normalize(const glm::vec3& v, const glm::vec3& fallback) {
  float len = glm::length(v);
  if (!(len > 1e-30f) || !std::isfinite(len)) return fallback;
  glm::vec3 n = v / len;
  if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return fallback;
  return n;
}

std::vector<glm::vec3> smooth_normals(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
  // Unnormalised cross products weight each face by its area.
  std::vector<glm::vec3> sum(positions.size(), glm::vec3(0.0f));
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    std::uint32_t a = indices[i], b = indices[i + 1], c = indices[i + 2];
    glm::vec3 n = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
    sum[a] += n, sum[b] += n, sum[c] += n;
  }
  std::vector<char> bad(positions.size(), 0);
  bool any_bad = false;
  for (std::size_t i = 0; i < sum.size(); ++i) {
    sum[i] = safe_normalize(sum[i], glm::vec3(0.0f));
    bad[i] = sum[i] == glm::vec3(0.0f);
    any_bad |= bad[i] != 0;
  }
  if (!any_bad) return sum;
  // Cancelling or degenerate neighbourhoods (two-sided sheets, zero-area faces): largest adjacent face,
  // else +Y.
  std::vector<float> best(positions.size(), 0.0f);
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    std::uint32_t v[3] = {indices[i], indices[i + 1], indices[i + 2]};
    glm::vec3 n = glm::cross(positions[v[1]] - positions[v[0]], positions[v[2]] - positions[v[0]]);
    float area = glm::length(n);
    if (!(area > 0.0f) || !std::isfinite(area)) continue;
    for (std::uint32_t k : v)
      if (bad[k] && area > best[k]) best[k] = area, sum[k] = n / area;
  }
  for (std::size_t i = 0; i < sum.size(); ++i)
    if (bad[i] && best[i] == 0.0f) sum[i] = {0.0f, 1.0f, 0.0f};
  return sum;
}

namespace {

// Corners of a triangle list grouped by the position they use (CSR: corners of p are
// corner[first[p] .. first[p + 1])), so each position's faces are found without a search.
struct CornersByPosition {
  std::vector<std::uint32_t> first, corner;
};
CornersByPosition corners_by_position(std::size_t positions, std::span<const std::uint32_t> indices) {
  CornersByPosition g;
  g.first.assign(positions + 1, 0);
  for (std::uint32_t v : indices) ++g.first[v + 1];
  for (std::size_t p = 0; p < positions; ++p) g.first[p + 1] += g.first[p];
  g.corner.resize(indices.size());
  std::vector<std::uint32_t> fill(g.first.begin(), g.first.end() - 1);
  for (std::size_t k = 0; k < indices.size(); ++k) g.corner[fill[indices[k]]++] = static_cast<std::uint32_t>(k);
  return g;
}

// Per face: the cross product (its length is twice the area, the weight) and its unit direction (zero
// for a degenerate face, which then has no direction to compare against a crease).
struct FaceNormals {
  std::vector<glm::vec3> weighted, unit;
};
FaceNormals face_normals(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
  FaceNormals f;
  f.weighted.reserve(indices.size() / 3);
  f.unit.reserve(indices.size() / 3);
  for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
    const glm::vec3& a = positions[indices[i]];
    glm::vec3 n = glm::cross(positions[indices[i + 1]] - a, positions[indices[i + 2]] - a);
    f.weighted.push_back(n);
    f.unit.push_back(safe_normalize(n, glm::vec3(0.0f)));
  }
  return f;
}

// Area-weighted sum over the faces of `corners` (one position) whose unit normal is within the crease of
// `face`'s. Summed in the same order for every corner, so corners with the same neighbour set get
// bit-identical normals and share a vertex.
glm::vec3 crease_sum(std::span<const std::uint32_t> corners, std::size_t face, const FaceNormals& f, float cos_crease) {
  glm::vec3 sum(0.0f);
  for (std::uint32_t k : corners)
    if (glm::dot(f.unit[face], f.unit[k / 3]) >= cos_crease) sum += f.weighted[k / 3];
  return sum;
}

}  // namespace

std::vector<glm::vec3> crease_normals(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                                      float crease_deg) {
  const std::size_t n = indices.size() / 3 * 3;
  indices = indices.first(n);
  const float cos_crease = std::cos(glm::radians(crease_deg));
  const CornersByPosition by_pos = corners_by_position(positions.size(), indices);
  const FaceNormals faces = face_normals(positions, indices);
  std::vector<glm::vec3> out(n, glm::vec3(0.0f));
  std::vector<glm::vec3> smooth;  // the whole-neighbourhood fallback, only computed when needed
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t p = indices[k];
    std::span<const std::uint32_t> around(by_pos.corner.data() + by_pos.first[p],
                                          by_pos.first[p + 1] - by_pos.first[p]);
    // A non-degenerate face counts itself and only faces within the crease (under 90 degrees), so its sum
    // does not cancel. A degenerate face (no direction), or a fan too large for the pairwise test, keeps
    // the plain smooth normal with its fallbacks.
    if (faces.unit[k / 3] != glm::vec3(0.0f) && around.size() <= kMaxCreaseFan) {
      out[k] = safe_normalize(crease_sum(around, k / 3, faces, cos_crease), faces.unit[k / 3]);
      continue;
    }
    if (smooth.empty()) smooth = smooth_normals(positions, indices);
    out[k] = smooth[p];
  }
  return out;
}

void assign_corner_normals(Scene& scene, std::size_t first_vertex, std::size_t first_index,
                           std::span<const glm::vec3> corner_normals) {
  // Copies made for a vertex are chained from it (next_copy), so a later corner finds the copy with its
  // normal; chains stay short (one link per crease through the vertex). Tables cover only the vertices
  // from first_vertex on, so a glTF file's many primitives cost linear time.
  constexpr std::uint32_t kNone = 0xffffffffu;
  const std::size_t n_vertices = scene.positions.size() - first_vertex;
  std::vector<char> missing(n_vertices, 0), assigned(n_vertices, 0);
  for (std::size_t v = 0; v < n_vertices; ++v) missing[v] = scene.normals[first_vertex + v] == glm::vec3(0.0f);
  std::vector<std::uint32_t> next_copy(n_vertices, kNone);  // local index of the next copy
  for (std::size_t k = 0; k < corner_normals.size(); ++k) {
    std::uint32_t& index = scene.indices[first_index + k];
    if (index < first_vertex || index - first_vertex >= n_vertices || !missing[index - first_vertex]) continue;
    const std::size_t v = index - first_vertex;
    const glm::vec3& n = corner_normals[k];
    if (!assigned[v]) {
      scene.normals[index] = n, assigned[v] = 1;
      continue;
    }
    std::size_t c = v, last = v;
    while (c != kNone && scene.normals[first_vertex + c] != n) last = c, c = next_copy[c];
    if (c == kNone) {
      c = scene.positions.size() - first_vertex;
      scene.positions.push_back(scene.positions[index]);
      scene.normals.push_back(n);
      next_copy.push_back(kNone);
      next_copy[last] = static_cast<std::uint32_t>(c);
    }
    index = static_cast<std::uint32_t>(first_vertex + c);
  }
}

void finalize(Scene& scene, const std::string& display, bool keep_normals) {
  if (scene.indices.empty())
    fail(
        fmt::format("{}: error: the scene has no triangles (an empty mesh cannot be rendered; add geometry)", display));
  if (scene.indices.size() % 3 != 0 || scene.normals.size() != scene.positions.size())
    fail(fmt::format("{}: error: internal: inconsistent geometry arrays (report a bug)", display));
  const std::size_t n = scene.positions.size();
  for (std::size_t i = 0; i < scene.indices.size(); ++i)
    if (scene.indices[i] >= n)
      fail(fmt::format("{}: error: triangle {} uses vertex {} of {} (fix the file's indices)", display, i / 3,
                       scene.indices[i], n));
  scene.bounds = Bounds{};
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3& p = scene.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(fmt::format("{}: error: vertex {} has a non-finite position (fix the file)", display, i));
    // The bounds' diagonal, the default AO radius and the reference's ray lengths square these in single
    // precision: beyond 1e18 the square of a distance overflows to inf (a "radius inf" far from its cause).
    if (std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > kMaxCoordinate)
      fail(fmt::format("{}: error: vertex {} is at ({:g}, {:g}, {:g}), beyond the {:g} world units a coordinate may "
                       "reach (rescale the scene, e.g. {}@scale=0.001)",
                       display, i, p.x, p.y, p.z, kMaxCoordinate, display));
    scene.bounds.extend(p);
    if (!keep_normals) scene.normals[i] = safe_normalize(scene.normals[i], {0.0f, 1.0f, 0.0f});
  }
  auto bytes = [](const auto& v) {
    return std::string_view(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(v[0]));
  };
  util::Hasher h;
  h.add("aovar-scene-1").add(bytes(scene.positions)).add(bytes(scene.normals)).add(bytes(scene.indices));
  scene.content_hash = h.hex();
}

}  // namespace detail

using namespace detail;

CameraPose camera_at(const View& view, int frame) {
  int frames = std::max(1, view.path_frames);
  int f = std::clamp(frame, 0, frames - 1);
  float t = frames > 1 ? static_cast<float>(f) / static_cast<float>(frames - 1) : 0.0f;
  return {view.eye + t * view.path_offset, view.target + t * view.path_offset, view.up};
}

const View& Scene::view(std::string_view wanted) const {
  for (const View& v : views)
    if (v.name == wanted) return v;
  std::string names;
  for (const View& v : views) names += (names.empty() ? "" : ", ") + v.name;
  fail(fmt::format("{}: error: no view '{}' (available: {})", name, wanted, names.empty() ? "none" : names));
}

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> out;
  for (const std::string& n : builtin_names()) out.push_back("builtin:" + n);
  return out;
}

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// "<scene>.views.toml" or "<scene>.views.json" next to the scene file, when exactly one exists.
fs::path side_file_for(const fs::path& scene_path) {
  fs::path toml = scene_path, json = scene_path;
  toml += ".views.toml";
  json += ".views.json";
  std::error_code ec;
  bool has_toml = fs::is_regular_file(toml, ec), has_json = fs::is_regular_file(json, ec);
  if (has_toml && has_json)
    fail(fmt::format("{}: error: both {} and {} exist (keep one views file)", util::display_path(scene_path),
                     util::display_path(toml), util::display_path(json)));
  return has_toml ? toml : has_json ? json : fs::path();
}

// A spec's trailing suffixes: SPEC[@scale=F][@tessellate=N], in either order, each at most once.
struct SpecSuffixes {
  std::string base;
  float scale = 1.0f;
  int tessellate = 0;  // levels; 0 = as loaded
};

// The number after a suffix, within [lo, hi]; fails naming the spec and the suffix otherwise.
struct SuffixRange {
  double lo, hi;
  std::string lo_text, hi_text, example;
};
double suffix_number(const std::string& spec, std::string_view suffix, const std::string& text, const SuffixRange& r) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(v >= r.lo && v <= r.hi))
    fail(fmt::format("{}: error: {} '{}' must be a number from {} to {} (e.g. {}{})", spec,
                     suffix.substr(1, suffix.size() - 2), text, r.lo_text, r.hi_text, suffix, r.example));
  return v;
}

SpecSuffixes split_suffixes(const std::string& spec) {
  SpecSuffixes out{spec};
  bool scaled = false, tessellated = false;
  for (std::size_t at; (at = out.base.rfind('@')) != std::string::npos;) {
    const std::string tail = out.base.substr(at);
    const bool is_scale = tail.starts_with(kScaleSuffix), is_tessellate = tail.starts_with(kTessellateSuffix);
    if (!is_scale && !is_tessellate) break;
    if ((is_scale && scaled) || (is_tessellate && tessellated))
      fail(fmt::format("{}: error: {} is given twice (give it once)", spec, is_scale ? kScaleSuffix : kTessellateSuffix));
    if (is_scale) {
      out.scale = static_cast<float>(
          suffix_number(spec, kScaleSuffix, tail.substr(kScaleSuffix.size()), {1e-6, 1e6, "1e-6", "1e6", "0.01"}));
      scaled = true;
    } else {
      const double n = suffix_number(spec, kTessellateSuffix, tail.substr(kTessellateSuffix.size()),
                                     {1, kMaxTessellateLevels, "1", std::to_string(kMaxTessellateLevels), "2"});
      if (n != std::floor(n)) fail(fmt::format("{}: error: tessellate '{:g}' must be a whole number", spec, n));
      out.tessellate = static_cast<int>(n);
      tessellated = true;
    }
    out.base.resize(at);
  }
  return out;
}

// Every length of the scene times f: geometry, the built-in radius and views. The views a side file gives
// are scaled after it is read (apply_views_file), so a views file keeps the units of its scene file.
void scale_scene(Scene& scene, float f) {
  if (f == 1.0f) return;
  for (glm::vec3& p : scene.positions) p *= f;
  scene.ao_radius *= f;
  for (View& v : scene.views) scale_view(v, f);
}

}  // namespace

Scene load_scene(const std::string& full_spec, const LoadOptions& options) {
  constexpr std::string_view kPrefix = "builtin:";
  const auto [spec, scale, levels] = split_suffixes(full_spec);
  Scene scene;
  fs::path views_file = options.views_file;
  if (spec.starts_with(kPrefix)) {
    const std::string_view name = std::string_view(spec).substr(kPrefix.size());
    scene = make_builtin(name);
    scale_scene(scene, scale);
    tessellate(scene, levels, full_spec);
    scene.name = full_spec;
    scene.source = "builtin";
    finalize(scene, spec, builtin_keeps_normals(name));
  } else {
    const fs::path path(spec);
    const std::string display = util::display_path(path);
    const std::string ext = lower(path.extension().string());
    if (ext != ".obj" && ext != ".gltf" && ext != ".glb") {
      std::string names;
      for (const std::string& n : builtin_scene_names()) names += (names.empty() ? "" : ", ") + n;
      fail(fmt::format("{}: error: unsupported scene format '{}' (supported: .obj, .gltf, .glb, or one of {})", display,
                       ext.empty() ? path.filename().string() : ext, names));
    }
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) fail(fmt::format("{}: error: cannot open (check the path)", display));
    if (!S_ISREG(st.st_mode))
      fail(fmt::format("{}: error: cannot read: it is {}, not a regular file (name a scene file)", display,
                       util::file_type_name(st.st_mode)));
    scene = ext == ".obj" ? load_obj(path, display, options) : load_gltf(path, display, options, ext == ".glb");
    scale_scene(scene, scale);
    tessellate(scene, levels, display);
    scene.name = full_spec;
    scene.source = display;
    finalize(scene, display);
    // Files carry no AO scale: 1.5% of the bounding-box diagonal is about a hand's width in a room-sized
    // scene and a few scale-lengths on a statue, the radius range SSAO papers show.
    scene.ao_radius = 0.015f * scene.bounds.diagonal();
    scene.views = derive_views(scene);
    if (views_file.empty()) views_file = side_file_for(path);
  }
  if (!views_file.empty()) apply_views_file(scene, views_file, scale);
  return scene;
}

}  // namespace aovar::scene
