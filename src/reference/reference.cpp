// Reference API: options, the cache, files, radius text and modes. Tracing is in trace.cpp.
#include "reference/reference.h"

#include <cmath>
#include <cstring>
#include <iostream>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "image/image.h"
#include "reference/detail.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::reference {

namespace fs = std::filesystem;

namespace {

// Bump when anything that changes traced pixels changes (sampling, offsets, camera, estimator).
constexpr std::string_view kCacheVersion = "aovar-reference-1";

std::uint64_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

void add_vec(util::Hasher& h, const glm::vec3& v) { h.add(bits(v.x)).add(bits(v.y)).add(bits(v.z)); }

fs::path with_suffix(const fs::path& stem, const char* suffix) {
  fs::path p = stem;
  p += suffix;
  return p;
}

void check_options(const ReferenceOptions& o) {
  if (o.size.width < 1 || o.size.height < 1)
    throw std::runtime_error(fmt::format("reference: size {}x{} is empty (use WxH with W, H >= 1)", o.size.width,
                                         o.size.height));
  if (!(o.radius > 0.0f) || !std::isfinite(o.radius))
    throw std::runtime_error(fmt::format("reference: radius {} must be a positive number of world units", o.radius));
  if (o.rays < 1 || o.rays > kMaxRays)
    throw std::runtime_error(fmt::format("reference: rays {} must be from 1 to {} per pixel", o.rays, kMaxRays));
  if (o.frame < 0) throw std::runtime_error(fmt::format("reference: frame {} must be 0 or more", o.frame));
  if (o.threads < 0) throw std::runtime_error(fmt::format("reference: threads {} must be 0 (all cores) or more", o.threads));
}

// The depth of a cache entry: <entry>.depth.pfm, or for an entry written before depth was cached, one
// primary ray per pixel (trace_depth: the same rays the reference traced), stored for the next run.
image::FloatImage cached_depth(const fs::path& entry, const scene::Scene& scene, const scene::View& view,
                               const ReferenceOptions& o) {
  const fs::path path = with_suffix(entry, ".depth.pfm");
  if (!fs::exists(path)) {
    image::FloatImage depth = trace_depth(scene, view, o.size, o.frame, o.threads).depth;
    try {
      image::write_pfm(path, depth);
    } catch (const std::exception&) {
      // As for the image: an unwritable cache costs the next run a trace, nothing else.
    }
    return depth;
  }
  image::FloatImage depth = image::read_pfm(path);
  if (depth.width != o.size.width || depth.height != o.size.height)
    throw std::runtime_error(fmt::format("{}: error: cached depth is {}x{}, expected {}x{}", util::display_path(path),
                                         depth.width, depth.height, o.size.width, o.size.height));
  for (float d : depth.pixels)  // a view depth is >= 0, +inf on background; NaN is damage
    if (!(d >= 0.0f))
      throw std::runtime_error(fmt::format("{}: error: cached depth holds {} (a depth is >= 0)", util::display_path(path), d));
  return depth;
}

}  // namespace

const char* mode_name(Mode m) { return m == Mode::obscurance ? "obscurance" : "occlusion"; }

Mode parse_mode(const std::string& text) {
  if (text == "occlusion") return Mode::occlusion;
  if (text == "obscurance") return Mode::obscurance;
  throw std::invalid_argument("unknown mode '" + text + "' (use occlusion or obscurance)");
}

float resolve_radius(const std::string& text, const scene::Scene& scene) {
  auto bad = [&](const std::string& why) {
    return std::invalid_argument(fmt::format(
        "radius '{}': {} (give world units such as 0.5, or a percentage of the bounding-box diagonal such as 1.5%)",
        text, why));
  };
  std::string number = text;
  bool percent = !number.empty() && number.back() == '%';
  if (percent) number.pop_back();
  double value = 0;
  std::size_t used = 0;
  try {
    value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size() || number.find_first_of(" \t") != std::string::npos)
    throw bad("not a number");
  if (!std::isfinite(value) || value <= 0) throw bad("must be positive");
  if (percent) {
    if (scene.bounds.empty() || scene.bounds.diagonal() <= 0) throw bad("the scene has no extent to take a percentage of");
    value = value / 100.0 * scene.bounds.diagonal();
  }
  return static_cast<float>(value);
}

std::string cache_key(const scene::Scene& scene, const scene::View& view, const ReferenceOptions& o) {
  util::Hasher h;
  h.add(kCacheVersion).add(scene.content_hash);
  h.add(view.name);
  add_vec(h, view.eye), add_vec(h, view.target), add_vec(h, view.up);
  h.add(bits(view.fov_y_deg)).add(bits(view.near_plane)).add(bits(view.far_plane));
  add_vec(h, view.path_offset);
  h.add(static_cast<std::uint64_t>(static_cast<std::int64_t>(view.path_frames)));
  h.add(static_cast<std::uint64_t>(o.frame));
  h.add(static_cast<std::uint64_t>(o.size.width)).add(static_cast<std::uint64_t>(o.size.height));
  h.add(bits(o.radius)).add(static_cast<std::uint64_t>(o.rays)).add(mode_name(o.mode));
  return h.hex();
}

void write_reference(const fs::path& stem, const ReferenceImage& ref) {
  image::FloatImage err = ref.std_error;
  for (std::size_t i = 0; i < err.pixels.size(); ++i)
    if (i < ref.background.size() && ref.background[i]) err.pixels[i] = -1.0f;
  // The visibility PFM goes last: its presence marks a complete entry (the cache looks for it).
  image::write_pfm(with_suffix(stem, ".stderr.pfm"), err);
  image::write_png(with_suffix(stem, ".png"), ref.visibility);
  image::write_pfm(with_suffix(stem, ".pfm"), ref.visibility);
}

ReferenceImage load_reference(const fs::path& stem) {
  ReferenceImage ref;
  ref.visibility = image::read_pfm(with_suffix(stem, ".pfm"));
  fs::path err_path = with_suffix(stem, ".stderr.pfm");
  ref.std_error = image::read_pfm(err_path);
  if (ref.std_error.width != ref.visibility.width || ref.std_error.height != ref.visibility.height)
    throw std::runtime_error(fmt::format("{}: error: {}x{} does not match the visibility image's {}x{}",
                                         util::display_path(err_path), ref.std_error.width, ref.std_error.height,
                                         ref.visibility.width, ref.visibility.height));
  ref.background.resize(ref.std_error.pixels.size());
  for (std::size_t i = 0; i < ref.std_error.pixels.size(); ++i) {
    ref.background[i] = ref.std_error.pixels[i] < 0.0f ? 1 : 0;
    if (ref.background[i]) ref.std_error.pixels[i] = 0.0f;
  }
  return ref;
}

namespace {

// A traced visibility is in [0, 1] and its standard error finite and >= 0 at every pixel: an entry of the
// right size holding NaN, Inf or values outside that range is damaged (it would make every error NaN).
void check_cached_values(const ReferenceImage& ref, const fs::path& file) {
  for (std::size_t i = 0; i < ref.visibility.pixels.size(); ++i) {
    const float v = ref.visibility.pixels[i];
    const float e = i < ref.std_error.pixels.size() ? ref.std_error.pixels[i] : 0.0f;
    if (!(v >= 0.0f && v <= 1.0f) || !(std::isfinite(e) && e >= 0.0f))
      throw std::runtime_error(fmt::format("{}: error: pixel {} holds visibility {} and standard error {} (a traced "
                                           "reference is finite, in [0, 1])",
                                           util::display_path(file), i, v, e));
  }
}

// The cached reference at `entry`, or nullopt when there is none or it is damaged (truncated, another
// size, unreadable): a damaged entry is traced again and replaced, with a warning, as the compile cache
// recompiles; the cache is a speed-up, never a reason to fail.
std::optional<ReferenceImage> cached_reference(const fs::path& entry, const scene::Scene& scene,
                                               const scene::View& view, const ReferenceOptions& o) {
  if (!fs::exists(with_suffix(entry, ".pfm"))) return std::nullopt;
  try {
    ReferenceImage ref = load_reference(entry);
    if (ref.visibility.width != o.size.width || ref.visibility.height != o.size.height)
      throw std::runtime_error(fmt::format("{}: error: cached reference is {}x{}, expected {}x{}",
                                           util::display_path(with_suffix(entry, ".pfm")), ref.visibility.width,
                                           ref.visibility.height, o.size.width, o.size.height));
    check_cached_values(ref, with_suffix(entry, ".pfm"));
    ref.depth = cached_depth(entry, scene, view, o);
    return ref;
  } catch (const std::exception& e) {
    std::cerr << "aovar: warning: " << e.what() << " (a damaged reference cache entry: tracing it again)\n";
    return std::nullopt;
  }
}

}  // namespace

ReferenceImage trace_reference(const scene::Scene& scene, const scene::View& view, const ReferenceOptions& options,
                               const Progress& progress) {
  check_options(options);
  if (scene.triangle_count() == 0) throw std::runtime_error(scene.name + ": error: the scene has no triangles to trace");
  const std::string key = cache_key(scene, view, options);
  fs::path entry;
  if (!options.cache_dir.empty()) {
    entry = options.cache_dir / "reference" / key;
    if (std::optional<ReferenceImage> cached = cached_reference(entry, scene, view, options)) {
      cached->key = key;
      cached->from_cache = true;
      if (progress) progress(1.0, 0.0);
      return std::move(*cached);
    }
  }
  ReferenceImage ref = detail::trace(scene, view, options, progress);
  ref.key = key;
  if (!entry.empty()) {
    try {
      image::write_pfm(with_suffix(entry, ".depth.pfm"), ref.depth);  // before the image, which marks a complete entry
      write_reference(entry, ref);
    } catch (const std::exception&) {
      // A cache that cannot be written only costs the next run a trace; the result is still good.
    }
  }
  return ref;
}

ReferenceStats reference_stats(const ReferenceImage& ref) {
  ReferenceStats s;
  double vis = 0, err = 0;
  std::size_t n = 0, background = 0;
  for (std::size_t i = 0; i < ref.visibility.pixels.size(); ++i) {
    if (i < ref.background.size() && ref.background[i]) {
      ++background;
      continue;
    }
    vis += ref.visibility.pixels[i];
    err += ref.std_error.pixels[i];
    ++n;
  }
  if (n > 0) s.mean_visibility = vis / static_cast<double>(n), s.mean_std_error = err / static_cast<double>(n);
  if (!ref.visibility.pixels.empty())
    s.background_share = static_cast<double>(background) / static_cast<double>(ref.visibility.pixels.size());
  return s;
}

}  // namespace aovar::reference
