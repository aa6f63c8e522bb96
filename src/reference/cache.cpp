#include "reference/cache.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace aovar::reference::detail {

namespace {

// The content's format; bumped when it changes (old entries then fail to decode and are traced again).
constexpr std::string_view kReferenceMagic = "aovar-reference-entry 1\n";

void put_u32_ref(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); }

void put_pixels(std::string& s, const std::vector<float>& pixels) {
  s.append(reinterpret_cast<const char*>(pixels.data()), pixels.size() * sizeof(float));
}

// Reads `n` floats from the front of `rest`, or throws (the checksum matched, so another build wrote it).
std::vector<float> take_pixels(std::string_view& rest, std::size_t n) {
  if (rest.size() < n * sizeof(float)) throw std::runtime_error("an image shorter than its size");
  std::vector<float> out(n);
  if (n) std::memcpy(out.data(), rest.data(), n * sizeof(float));
  rest.remove_prefix(n * sizeof(float));
  return out;
}

std::uint32_t take_u32_ref(std::string_view& rest) {
  if (rest.size() < sizeof(std::uint32_t)) throw std::runtime_error("a truncated header");
  std::uint32_t v;
  std::memcpy(&v, rest.data(), sizeof v);
  rest.remove_prefix(sizeof v);
  return v;
}

// A traced visibility is in [0, 1], its standard error finite and >= 0 (-1 marks background), and a view
// depth >= 0 (+inf on background): anything else is damage, and would make every error NaN.
void check_traced_values(const ReferenceImage& ref) {
  for (std::size_t i = 0; i < ref.visibility.pixels.size(); ++i) {
    const float v = ref.visibility.pixels[i], e = ref.std_error.pixels[i], d = ref.depth.pixels[i];
    if (!(v >= 0.0f && v <= 1.0f) || !(std::isfinite(e) && e >= 0.0f) || !(d >= 0.0f))
      throw std::runtime_error(fmt::format("pixel {} holds visibility {}, standard error {} and depth {} (a traced "
                                           "reference is finite, in [0, 1], at a depth >= 0)",
                                           i, v, e, d));
  }
}

ReferenceImage decode_reference(std::string_view rest, render::Extent size) {
  if (rest.substr(0, kReferenceMagic.size()) != kReferenceMagic) throw std::runtime_error("not a reference image");
  rest.remove_prefix(kReferenceMagic.size());
  const std::uint32_t w = take_u32_ref(rest), h = take_u32_ref(rest);
  if (w != static_cast<std::uint32_t>(size.width) || h != static_cast<std::uint32_t>(size.height))
    throw std::runtime_error(fmt::format("a reference of {}x{}, expected {}x{}", w, h, size.width, size.height));
  const std::size_t n = std::size_t(w) * h;
  ReferenceImage ref;
  for (image::FloatImage* img : {&ref.visibility, &ref.std_error, &ref.depth}) {
    img->width = size.width, img->height = size.height;
    img->pixels = take_pixels(rest, n);
  }
  if (!rest.empty()) throw std::runtime_error("bytes after the images");
  ref.background.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    ref.background[i] = ref.std_error.pixels[i] == -1.0f ? 1 : 0;  // stored as -1 on background (store())
    if (ref.background[i]) ref.std_error.pixels[i] = 0.0f;
  }
  check_traced_values(ref);
  return ref;
}

}  // namespace

std::optional<ReferenceImage> ReferenceCache::find(const std::string& key, render::Extent size) const {
  const std::optional<std::string> content = cache_.read(entry_key(key));
  if (!content) return std::nullopt;
  try {
    return decode_reference(*content, size);
  } catch (const std::exception& e) {
    cache_.reject(entry_key(key), e.what());
    return std::nullopt;
  }
}

void ReferenceCache::store(const std::string& key, const ReferenceImage& ref) const {
  if (!enabled()) return;
  std::string s(kReferenceMagic);
  put_u32_ref(s, static_cast<std::uint32_t>(ref.visibility.width));
  put_u32_ref(s, static_cast<std::uint32_t>(ref.visibility.height));
  image::FloatImage err = ref.std_error;
  for (std::size_t i = 0; i < err.pixels.size(); ++i)
    if (i < ref.background.size() && ref.background[i]) err.pixels[i] = -1.0f;
  put_pixels(s, ref.visibility.pixels);
  put_pixels(s, err.pixels);
  put_pixels(s, ref.depth.pixels);
  cache_.write(entry_key(key), s);  // an unwritable cache warns once and only costs the next run a trace
}

}  // namespace aovar::reference::detail
