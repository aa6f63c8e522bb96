// Camera views: derived from the geometry for file scenes, and read from views side files.
//
// Views side file: "<scene file>.views.toml" / ".views.json" next to the scene (found automatically), or
// any file given as LoadOptions::views_file (also for built-in scenes). TOML:
//
//   [[view]]
//   name = "overview"          # required, unique
//   eye = [x, y, z]            # required, world space (metres for the built-in scenes)
//   target = [x, y, z]         # required, different from eye
//   up = [0, 1, 0]             # optional (default +Y), not parallel to target - eye
//   fov = 60                   # optional, vertical, degrees, 0 < fov < 180 (default 60)
//   near = 0.1                 # optional (default 0.1% of the scene's bounding-box diagonal), > 0, finite
//   far = 50                   # optional (default: just beyond the farthest bounding-box corner), > near;
//                              # far = inf gives an infinite projection (render/frame.h)
//   path_offset = [0.2, 0, 0]  # optional: eye and target move by this over the camera path (default none)
//   path_frames = 8            # optional, >= 1 (default 8)
//
// JSON: {"views": [{"name": "overview", "eye": [x, y, z], ...same keys...}, ...]}. JSON has no infinity
// literal: "far": "inf" (a string) stands for TOML's far = inf.
//
// A view named overview, closeup or background replaces the derived (or built-in) one; other names are
// added after them. Errors name the file, line and column.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "scene/detail.h"
#include "util/fs.h"
#include "util/path_names.h"

namespace aovar::scene::detail {
namespace fs = std::filesystem;

namespace {

glm::vec3 right_of(const View& v) { return safe_normalize(glm::cross(v.target - v.eye, v.up), {1, 0, 0}); }

// Looks from `eye` at the first thing a ray towards `aim` hits, with the eye moved along that ray to `dist`
// from it: forwards when the hit is farther (the segment up to the hit is empty), backwards into free space
// when it is nearer. Nothing, or a back face (the eye is inside something): no view.
std::optional<View> look_at_hit(const RayCaster& rc, const glm::vec3& eye, const glm::vec3& aim, float dist) {
  glm::vec3 d = safe_normalize(aim - eye, {0, 0, -1});
  Hit h = rc.cast(eye, d);
  if (!h || !h.front) return std::nullopt;
  View v;
  v.target = eye + h.t * d;
  float back = 0.0f;
  if (h.t < dist) {
    Hit behind = rc.cast(eye, -d, dist);
    back = std::min(dist - h.t, behind ? 0.8f * behind.t : dist);
  }
  v.eye = v.target - (std::min(dist, h.t) + back) * d;
  return v;
}

// Distance from `centre` along `from` at which all corners of `b` fit a 60 degree vertical field of view
// at 4:3 (wider frames fit too), with a 5% margin.
float fit_distance(const Bounds& b, const glm::vec3& centre, const glm::vec3& from) {
  const glm::vec3 fwd = -from, r = glm::normalize(glm::cross(fwd, glm::vec3(0, 1, 0))), u = glm::cross(r, fwd);
  const float ty = std::tan(glm::radians(30.0f)), tx = ty * 4.0f / 3.0f;
  float d = 0.0f;
  for (int i = 0; i < 8; ++i) {
    glm::vec3 q = glm::vec3(i & 1 ? b.max.x : b.min.x, i & 2 ? b.max.y : b.min.y, i & 4 ? b.max.z : b.min.z) - centre;
    float z = glm::dot(q, fwd);
    d = std::max({d, std::fabs(glm::dot(q, r)) / tx - z, std::fabs(glm::dot(q, u)) / ty - z});
  }
  return 1.05f * d;
}

// Of the rays around a standpoint (hit, direction; not empty), the direction of the first of the nearest
// within 0.1 %: symmetric scenes (Sponza's nave) have mirrored nearest walls that rounding would pick
// between differently at another scale.
glm::vec3 nearest_direction(const std::vector<std::pair<Hit, glm::vec3>>& around) {
  const float t_min = std::min_element(around.begin(), around.end(), [](const auto& a, const auto& b) {
                        return a.first.t < b.first.t;
                      })->first.t;
  return std::find_if(around.begin(), around.end(), [&](const auto& a) { return a.first.t <= t_min * 1.001f; })->second;
}

}  // namespace

void fit_planes(View& view, const Bounds& bounds, float near) {
  float far = 0.0f;
  for (const glm::vec3& eye : {view.eye, view.eye + view.path_offset})
    for (int i = 0; i < 8; ++i) {
      glm::vec3 corner(i & 1 ? bounds.max.x : bounds.min.x, i & 2 ? bounds.max.y : bounds.min.y,
                       i & 4 ? bounds.max.z : bounds.min.z);
      far = std::max(far, glm::length(corner - eye));
    }
  view.near_plane = near;
  view.far_plane = std::max(far * 1.02f, near * 2.0f);
}

std::vector<View> derive_views(const Scene& s) {
  const Bounds& b = s.bounds;
  const glm::vec3 c = b.center(), size = b.max - b.min;
  const float diag = std::max(b.diagonal(), 1e-6f);
  const float near = diag * 1e-3f;  // far / near stays below ~3000 for every derived view
  const RayCaster rc(s);

  // Interior standpoint: 5% of the diagonal above the floor under the middle, when there is a floor there
  // (the downward ray meets a front face) and no ray around it meets a back face (not inside something).
  std::optional<glm::vec3> inside;
  std::vector<std::pair<Hit, glm::vec3>> around;
  if (Hit down = rc.cast(c, {0, -1, 0}); down && down.front && down.t > 0.05f * diag) {
    inside = c - glm::vec3(0, down.t - 0.05f * diag, 0);
    for (int k = 0; k < 16; ++k) {
      float yaw = glm::radians(22.5f * static_cast<float>(k));
      glm::vec3 d = glm::normalize(glm::vec3(std::cos(yaw), -std::tan(glm::radians(10.0f)), std::sin(yaw)));
      Hit h = rc.cast(*inside, d);
      if (h && !h.front) inside.reset();
      if (!inside) break;
      if (h) around.emplace_back(h, d);
    }
  }

  // Overview: from front-right-above, far enough for the bounding box to fit the frame, at the middle.
  // Enclosed scenes (an atrium, a room: there is an interior standpoint, and from outside the centre ray
  // stops at the shell or meets a back face) would show only their outside; there the overview looks
  // instead along the longer horizontal axis from high up near one end, down at the middle.
  View overview;
  overview.name = "overview";
  const glm::vec3 from = glm::normalize(glm::vec3(0.5f, 0.6f, 1.0f));
  const float dist = std::max(fit_distance(b, c, from), 0.5f * diag);
  overview.eye = c + from * dist;
  overview.target = c;
  const Hit centre = rc.cast(overview.eye, -from);
  glm::vec3 inv_from = 1.0f / -from;  // entry distance into the bounding box along the centre ray
  glm::vec3 t_lo = (b.min - overview.eye) * inv_from, t_hi = (b.max - overview.eye) * inv_from;
  glm::vec3 t_near = glm::min(t_lo, t_hi);
  const float entry = std::max({t_near.x, t_near.y, t_near.z});
  if (inside && centre && (!centre.front || centre.t < entry + 0.05f * diag)) {
    const glm::vec3 axis = size.x >= size.z ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
    const glm::vec3 d = glm::normalize(axis + glm::vec3(0, 0.25f, 0));
    Hit wall = rc.cast(c, d);
    overview.eye = c + d * (wall ? 0.85f * wall.t : 0.45f * glm::dot(size, axis));
    overview.target = c - glm::vec3(0, 0.25f * size.y, 0);
  } else if (!centre) {
    // Hollow middle (a ring, an arch): aim at the geometry nearest the middle of the frame.
    float best = -1.0f;
    for (int i = 0; i < 27; ++i) {
      glm::vec3 p = c + 0.5f * size * (glm::vec3(i % 3, i / 3 % 3, i / 9) - 1.0f);
      glm::vec3 d = glm::normalize(p - overview.eye);
      Hit h = rc.cast(overview.eye, d);
      float align = glm::dot(d, -from);
      if (h && align > best) best = align, overview.target = overview.eye + h.t * d;
    }
  }
  overview.path_offset = right_of(overview) * (0.02f * glm::length(overview.target - overview.eye));
  fit_planes(overview, b, near);

  // Closeup at 12% of the diagonal. From the interior standpoint: at the nearest thing around, slightly
  // below eye level (a column base, a wall foot, a block). Otherwise (objects): from outside, at the lower
  // middle of the geometry.
  const float close = 0.12f * diag;
  std::optional<View> closeup;
  if (inside && !around.empty()) {
    closeup = look_at_hit(rc, *inside, *inside + nearest_direction(around), close);
  }
  if (!closeup) {
    const glm::vec3 low(c.x, b.min.y + 0.15f * size.y, c.z);
    const glm::vec3 eye = c + glm::normalize(glm::vec3(0.6f, 0.25f, 1.0f)) * (0.6f * diag);
    closeup = look_at_hit(rc, eye, low, close);
    if (!closeup) closeup = look_at_hit(rc, eye, c, close);
    if (!closeup) closeup = look_at_hit(rc, overview.eye, overview.target, close);
    if (!closeup) {  // nothing front-facing found: keep a sane camera anyway
      closeup = View{};
      closeup->target = c;
      closeup->eye = c + from * close;
    }
  }
  closeup->name = "closeup";
  closeup->path_offset = right_of(*closeup) * (0.03f * glm::length(closeup->target - closeup->eye));
  fit_planes(*closeup, b, near);

  // Background: of a few candidates, the one whose frame is nearest 40% empty (preferring 20-60%). From
  // the interior standpoint, tried first: looking up out of the top at four pitches along both horizontal
  // axes. From outside, when no interior view is in range: the eye just above the bounding box, pitched
  // down 10 or 20 degrees, so that everything above the horizon (a fifth of the frame or more) is empty and
  // the geometry fills the rest; a roof seen from above would be a poor view of an interior.
  View background;
  float best = 1e30f;
  auto consider = [&](View v) {
    fit_planes(v, b, near);
    float share = rc.miss_share(v, 32, 18);
    float score = std::fabs(share - 0.4f) + (share < 0.2f || share > 0.6f ? 1.0f : 0.0f);
    if (score < best) best = score, background = v;
  };
  if (inside)
    for (float yaw : {0.0f, 90.0f})
      for (float pitch : {35.0f, 50.0f, 65.0f, 80.0f}) {
        View v;
        v.eye = *inside;
        float y = glm::radians(yaw), p = glm::radians(pitch);
        v.target = v.eye + diag * glm::vec3(std::cos(p) * std::cos(y), std::sin(p), std::cos(p) * std::sin(y));
        consider(v);
      }
  if (best >= 1.0f)
    for (glm::vec3 h : {glm::vec3(0.5f, 0.0f, 1.0f), glm::vec3(-1.0f, 0.0f, 0.3f)})
      for (float away : {0.7f, 0.4f})  // the nearer for single objects, which leave much of a frame empty
        for (float pitch : {10.0f, 20.0f}) {
          View v;
          h = glm::normalize(h);
          v.eye = glm::vec3(c.x, b.max.y + 0.05f * size.y, c.z) + h * (away * diag);
          v.target = v.eye - diag * (h + glm::vec3(0, std::tan(glm::radians(pitch)), 0));
          consider(v);
        }
  background.name = "background";
  return {overview, *closeup, background};
}

// ---- views side files ----

namespace {

// More frames than a flicker measure needs by far, and few enough to render: the cap on path_frames.
constexpr std::int64_t kMaxPathFrames = 100000;
constexpr std::string_view kKeys = "name, eye, target, up, fov, near, far, path_offset, path_frames";

struct Pos {
  std::size_t line = 0, column = 0;
};

std::string lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

// Builds and checks views from either format. NaN near/far = not given (fitted to the scene later).
class ViewsFile {
 public:
  explicit ViewsFile(std::string display) : display_(std::move(display)) {}

  [[noreturn]] void error(Pos p, const std::string& what) const {
    if (p.line == 0) fail(fmt::format("{}: error: {}", display_, what));
    fail(fmt::format("{}:{}:{}: error: {}", display_, p.line, p.column, what));
  }

  void unknown_key(Pos p, std::string_view key, std::size_t view_index) const {
    error(p, fmt::format("unknown key '{}' in view {} (expected one of: {})", key, view_index + 1, kKeys));
  }

  // One key of a view in either syntax; the getters read the node as the key's type or report an error.
  template <class Str, class Num, class Vec, class Int>
  void set_key(View& v, std::string_view k, Pos p, std::size_t view_index, bool& has_eye, bool& has_target,
               Str string, Num number, Vec vec3, Int whole) const {
    if (k == "name") v.name = string();
    else if (k == "eye") v.eye = vec3(), has_eye = true;
    else if (k == "target") v.target = vec3(), has_target = true;
    else if (k == "up") v.up = vec3();
    else if (k == "path_offset") v.path_offset = vec3();
    else if (k == "fov") v.fov_y_deg = number();
    else if (k == "near") v.near_plane = number();
    else if (k == "far") v.far_plane = number();
    else if (k == "path_frames") {
      std::optional<std::int64_t> n = whole();
      if (!n || *n < 1 || *n > kMaxPathFrames)
        error(p, fmt::format("'path_frames' must be a whole number from 1 to {} (frames rendered along the camera path)",
                             kMaxPathFrames));
      v.path_frames = static_cast<int>(*n);
    } else {
      unknown_key(p, k, view_index);
    }
  }

  View start() const {
    View v;
    v.near_plane = v.far_plane = std::numeric_limits<float>::quiet_NaN();
    return v;
  }

  // Checks a view once its keys are read; `at` is the view's own position, `key_pos` those of its keys.
  void finish(View& v, bool has_eye, bool has_target, Pos at, const std::map<std::string, Pos>& key_pos) {
    auto pos = [&](const char* key) {
      auto it = key_pos.find(key);
      return it == key_pos.end() ? at : it->second;
    };
    const std::string label = v.name.empty() ? fmt::format("view {}", views.size() + 1) : "view '" + v.name + "'";
    if (v.name.empty()) error(at, label + " has no name (add name = \"overview\", \"closeup\", ...)");
    // The name becomes the view's image file names (reference, every variant's image): one plain component.
    if (std::string why = util::path_component_problem(v.name); !why.empty())
      error(pos("name"), fmt::format("view name '{}' {}: it names the view's image files (use letters, digits, "
                                     "'-', '_', '.')", util::printable_name(v.name), why));
    // NaN near/far means "not given" (start()), so a NaN written in the file (TOML nan) is caught here, by key.
    if (key_pos.count("near") && std::isnan(v.near_plane))
      error(pos("near"), label + ": near nan is not a number (e.g. near = 0.1)");
    if (key_pos.count("far") && std::isnan(v.far_plane))
      error(pos("far"), label + ": far nan is not a number (e.g. far = 50, or far = inf)");
    const std::pair<const char*, const glm::vec3*> points[] = {
        {"eye", &v.eye}, {"target", &v.target}, {"up", &v.up}, {"path_offset", &v.path_offset}};
    for (auto [key, p] : points)
      if (!std::isfinite(p->x) || !std::isfinite(p->y) || !std::isfinite(p->z))
        error(pos(key), fmt::format("{}: {} must be finite (no inf or nan)", label, key));
    for (const View& o : views)
      if (o.name == v.name)
        error(pos("name"), fmt::format("view '{}' is defined twice (rename or remove one)", v.name));
    if (!has_eye) error(at, label + " has no eye (add eye = [x, y, z])");
    if (!has_target) error(at, label + " has no target (add target = [x, y, z])");
    if (glm::length(v.target - v.eye) < 1e-6f)
      error(pos("target"), label + ": eye and target are the same point (move the target to where the camera looks)");
    if (!(v.fov_y_deg > 0.0f && v.fov_y_deg < 180.0f))
      error(pos("fov"), fmt::format("{}: fov {} is outside (0, 180) (the vertical field of view in degrees, e.g. 60)",
                                    label, v.fov_y_deg));
    if (!std::isnan(v.near_plane) && !(v.near_plane > 0.0f && std::isfinite(v.near_plane)))
      error(pos("near"), fmt::format("{}: near {} must be > 0 and finite (e.g. 0.1)", label, v.near_plane));
    if (!std::isnan(v.far_plane) && !std::isnan(v.near_plane) && !(v.far_plane > v.near_plane))
      error(pos("far"), fmt::format("{}: far {} must be greater than near {}", label, v.far_plane, v.near_plane));
    if (!std::isnan(v.far_plane) && !(v.far_plane > 0.0f))
      error(pos("far"), fmt::format("{}: far {} must be > 0", label, v.far_plane));
    glm::vec3 f = v.target - v.eye;
    if (!(glm::length(glm::cross(f, v.up)) > 1e-6f * glm::length(f) * glm::length(v.up)))
      error(pos("up"), label + ": up is zero or parallel to the viewing direction (e.g. up = [0, 1, 0])");
    if (v.path_frames < 1) error(pos("path_frames"), fmt::format("{}: path_frames must be at least 1", label));
    views.push_back(std::move(v));
  }

  std::vector<View> views;

 private:
  std::string display_;
};

// ---- TOML ----

Pos pos_of(const toml::source_region& r) { return {r.begin.line, r.begin.column}; }

std::vector<View> parse_toml(const std::string& text, const std::string& display) {
  ViewsFile vf(display);
  toml::table doc;
  try {
    doc = toml::parse(text, display);
  } catch (const toml::parse_error& e) {
    vf.error(pos_of(e.source()), std::string(e.description()) + " (fix the TOML syntax)");
  }
  for (auto&& [k, node] : doc)
    if (k.str() != "view")
      vf.error(pos_of(k.source()), fmt::format("unknown key '{}' (a views file holds [[view]] tables)", k.str()));
  const toml::node* list = doc.get("view");
  const toml::array* arr = list ? list->as_array() : nullptr;
  if (!arr || arr->empty() || !arr->is_array_of_tables())
    vf.error(list ? pos_of(list->source()) : Pos{1, 1},
             "no [[view]] tables (add [[view]] with name, eye and target; see the format in src/scene/views.cpp)");
  for (const toml::node& vn : *arr) {
    const toml::table& t = *vn.as_table();
    View v = vf.start();
    bool has_eye = false, has_target = false;
    std::map<std::string, Pos> key_pos;
    for (auto&& entry : t) {  // not a structured binding: clang 14 cannot capture one in the lambdas below
      const toml::key& key = entry.first;
      const toml::node& node = entry.second;
      const std::string k(key.str());
      const Pos p = pos_of(key.source());
      key_pos[k] = p;
      auto number = [&]() -> float {
        std::optional<double> d = node.value<double>();
        if (!d) vf.error(p, fmt::format("'{}' must be a number", k));
        return static_cast<float>(*d);
      };
      auto vec3 = [&]() -> glm::vec3 {
        const toml::array* a = node.as_array();
        glm::vec3 out;
        if (!a || a->size() != 3) vf.error(p, fmt::format("'{}' must be a list of 3 numbers, e.g. [0, 1, 0]", k));
        for (int i = 0; i < 3; ++i) {
          std::optional<double> d = (*a)[static_cast<std::size_t>(i)].value<double>();
          if (!d) vf.error(p, fmt::format("'{}' must be a list of 3 numbers, e.g. [0, 1, 0]", k));
          out[i] = static_cast<float>(*d);
        }
        return out;
      };
      auto string = [&]() -> std::string {
        std::optional<std::string> s = node.value<std::string>();
        if (!s) vf.error(p, "'name' must be a string");
        return *s;
      };
      auto whole = [&]() { return node.value<std::int64_t>(); };
      vf.set_key(v, k, p, vf.views.size(), has_eye, has_target, string, number, vec3, whole);
    }
    vf.finish(v, has_eye, has_target, pos_of(t.source()), key_pos);
  }
  return std::move(vf.views);
}

// ---- JSON ----

Pos pos_at(const std::string& text, std::size_t offset) {
  Pos p{1, 1};
  for (std::size_t i = 0; i < offset && i < text.size(); ++i)
    if (text[i] == '\n')
      ++p.line, p.column = 1;
    else
      ++p.column;
  return p;
}

// nlohmann keeps no source positions, so a light scan of the (already valid) text finds where each object
// of the top-level "views" array starts and where its keys are.
struct JsonLayout {
  std::vector<std::size_t> view_start;
  std::vector<std::map<std::string, std::size_t>> keys;
};

JsonLayout scan_json(const std::string& text) {
  JsonLayout out;
  std::string stack, root_key;
  bool in_views = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char ch = text[i];
    if (ch == '"') {
      std::size_t start = i++;
      std::string s;
      for (; i < text.size() && text[i] != '"'; ++i) {
        if (text[i] == '\\')
          ++i;
        else
          s += text[i];
      }
      std::size_t j = i + 1;
      while (j < text.size() && std::isspace(static_cast<unsigned char>(text[j]))) ++j;
      if (j < text.size() && text[j] == ':') {
        if (stack.size() == 1) root_key = s;
        // A key of a view object (not of an array nested at the same depth: "[[...]]" has no keys).
        if (stack.size() == 3 && in_views && stack.back() == '{' && !out.keys.empty()) out.keys.back()[s] = start;
      }
    } else if (ch == '{' || ch == '[') {
      stack += ch;
      if (stack.size() == 2 && ch == '[' && root_key == "views") in_views = true;
      if (stack.size() == 3 && ch == '{' && in_views) out.view_start.push_back(i), out.keys.emplace_back();
    } else if (ch == '}' || ch == ']') {
      if (stack.size() == 2) in_views = false;
      if (!stack.empty()) stack.pop_back();
    }
  }
  return out;
}

std::vector<View> parse_json(const std::string& text, const std::string& display) {
  ViewsFile vf(display);
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    std::string msg = e.what();
    if (auto close = msg.find("] "); close != std::string::npos) msg.erase(0, close + 2);
    vf.error(pos_at(text, e.byte > 0 ? e.byte - 1 : 0), msg + " (fix the JSON syntax)");
  } catch (const nlohmann::json::out_of_range& e) {  // "number overflow parsing '1e400'": no byte offset
    std::string msg = e.what();
    if (auto close = msg.find("] "); close != std::string::npos) msg.erase(0, close + 2);
    const std::size_t open = msg.find('\''), close = open == std::string::npos ? open : msg.find('\'', open + 1);
    const std::size_t at = close == std::string::npos ? std::string::npos : text.find(msg.substr(open + 1, close - open - 1));
    vf.error(at == std::string::npos ? Pos{} : pos_at(text, at),
             msg + " (a number beyond the range of a double: views need finite numbers)");
  }
  const JsonLayout layout = scan_json(text);
  if (!doc.is_object()) vf.error({1, 1}, "the file must be a JSON object {\"views\": [...]}");
  for (auto& [k, _] : doc.items())
    if (k != "views") vf.error({1, 1}, fmt::format("unknown key '{}' (a views file holds {{\"views\": [...]}})", k));
  if (!doc.contains("views") || !doc["views"].is_array() || doc["views"].empty())
    vf.error({1, 1}, "no views (add {\"views\": [{\"name\": ..., \"eye\": [x, y, z], \"target\": [x, y, z]}]})");
  const nlohmann::json& list = doc["views"];
  for (std::size_t vi = 0; vi < list.size(); ++vi) {
    const nlohmann::json& o = list[vi];
    const bool located = vi < layout.view_start.size();
    const Pos at = located ? pos_at(text, layout.view_start[vi]) : Pos{};
    if (!o.is_object()) vf.error(at, fmt::format("view {} must be an object", vi + 1));
    std::map<std::string, Pos> key_pos;
    View v = vf.start();
    bool has_eye = false, has_target = false;
    for (auto& [k, node] : o.items()) {
      Pos p = at;
      if (located)
        if (auto it = layout.keys[vi].find(k); it != layout.keys[vi].end()) p = pos_at(text, it->second);
      key_pos[k] = p;
      auto number = [&, &node = node, &k = k]() -> float {
        // JSON has no infinity literal: the far plane takes the string "inf" for TOML's far = inf.
        if (k == "far" && node.is_string() && lower(node.get<std::string>()) == "inf")
          return std::numeric_limits<float>::infinity();
        if (!node.is_number()) vf.error(p, fmt::format("'{}' must be a number{}", k, k == "far" ? " or \"inf\"" : ""));
        return node.get<float>();
      };
      auto vec3 = [&, &node = node, &k = k]() -> glm::vec3 {
        if (!node.is_array() || node.size() != 3 || !node[0].is_number() || !node[1].is_number() ||
            !node[2].is_number())
          vf.error(p, fmt::format("'{}' must be a list of 3 numbers, e.g. [0, 1, 0]", k));
        return {node[0].template get<float>(), node[1].template get<float>(), node[2].template get<float>()};
      };
      auto string = [&, &node = node]() -> std::string {
        if (!node.is_string()) vf.error(p, "'name' must be a string");
        return node.get<std::string>();
      };
      auto whole = [&, &node = node]() -> std::optional<std::int64_t> {
        if (!node.is_number_integer()) return std::nullopt;
        return node.get<std::int64_t>();
      };
      vf.set_key(v, k, p, vi, has_eye, has_target, string, number, vec3, whole);
    }
    vf.finish(v, has_eye, has_target, at, key_pos);
  }
  return std::move(vf.views);
}

}  // namespace

void scale_view(View& v, float f) {
  v.eye *= f, v.target *= f, v.path_offset *= f;
  v.near_plane *= f, v.far_plane *= f;  // NaN (not given) and inf stay what they are
}

void apply_views_file(Scene& scene, const fs::path& path, float scale) {
  const std::string display = util::display_path(path);
  std::optional<std::string> text;
  try {
    text = util::read_file(path);
  } catch (const util::ReadError& e) {
    fail(e.what());  // a SceneError, as every other problem of a scene's inputs
  }
  if (!text) fail(fmt::format("{}: error: cannot open views file (check the path)", display));
  const std::string ext = lower(path.extension().string());
  // nlohmann's parser stops at a NUL as at the end of the input, so text after one would be ignored.
  if (const std::size_t nul = text->find('\0'); nul != std::string::npos) {
    const Pos p = pos_at(*text, nul);
    fail(fmt::format("{}:{}:{}: error: a NUL byte (a views file is text: export it again)", display, p.line,
                     p.column));
  }
  std::vector<View> views;
  if (ext == ".toml")
    views = parse_toml(*text, display);
  else if (ext == ".json")
    views = parse_json(*text, display);
  else
    fail(fmt::format("{}: error: unsupported views file format '{}' (use .toml or .json)", display, ext));

  const float near = std::max(scene.bounds.diagonal() * 1e-3f, 1e-6f);
  for (View& v : views) {
    scale_view(v, scale);
    const float given_near = v.near_plane, given_far = v.far_plane;
    fit_planes(v, scene.bounds, std::isnan(given_near) ? near : given_near);
    if (!std::isnan(given_far)) v.far_plane = given_far;
    if (!(v.far_plane > v.near_plane))
      fail(
          fmt::format("{}: error: view '{}': near {} is beyond the scene (farthest point {}; set far or a smaller "
                      "near)",
                      display, v.name, v.near_plane, v.far_plane));
    auto same = std::find_if(scene.views.begin(), scene.views.end(), [&](const View& o) { return o.name == v.name; });
    if (same != scene.views.end())
      *same = std::move(v);
    else
      scene.views.push_back(std::move(v));
  }
}

}  // namespace aovar::scene::detail
