// Reference API: options, the cache, files, radius text and modes. Tracing is in trace.cpp.
#include "reference/reference.h"

#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "image/image.h"
#include "reference/cache.h"
#include "reference/detail.h"
#include "util/fs.h"
#include "util/hash.h"
#include "util/parse_number.h"

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
  const auto whole = util::whole_double(number);
  if (!whole || number.find_first_of(" \t") != std::string::npos) throw bad("not a number");
  double value = *whole;
  if (!std::isfinite(value) || value <= 0) throw bad("must be positive");
  if (percent) {
    if (scene.bounds.empty() || scene.bounds.diagonal() <= 0) throw bad("the scene has no extent to take a percentage of");
    value = value / 100.0 * scene.bounds.diagonal();
  }
  return static_cast<float>(value);
}

double surface_rmse(const ReferenceImage& a, const ReferenceImage& b) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.visibility.pixels.size(); ++i) {
    if (a.background[i] || b.background[i]) continue;
    const double d = double(a.visibility.pixels[i]) - double(b.visibility.pixels[i]);
    sum += d * d;
    ++n;
  }
  return n ? std::sqrt(sum / double(n)) : 0.0;
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

ReferenceImage trace_reference(const scene::Scene& scene, const scene::View& view, const ReferenceOptions& options,
                               const Progress& progress) {
  check_options(options);
  if (scene.triangle_count() == 0) throw std::runtime_error(scene.name + ": error: the scene has no triangles to trace");
  const std::string key = cache_key(scene, view, options);
  const detail::ReferenceCache cache(options.cache_dir);
  if (std::optional<ReferenceImage> cached = cache.find(key, options.size)) {
    cached->key = key;
    cached->from_cache = true;
    if (progress) progress(1.0, 0.0);
    return std::move(*cached);
  }
  ReferenceImage ref = detail::trace(scene, view, options, progress);
  ref.key = key;
  cache.store(key, ref);
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
