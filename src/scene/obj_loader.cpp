// Wavefront OBJ through tinyobjloader (float build): triangulated, all shapes merged, one vertex per
// distinct (position, normal) pair. Normals missing from the file (or zero) are computed smooth per
// position. tinyobjloader reports problems without the offending line (or with the last line), so on any
// problem the text is rescanned here to name the first bad line.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include "scene/detail.h"
#include "util/fs.h"

namespace aovar::scene::detail {
namespace {

struct Problem {
  std::size_t line = 0;
  std::string what;
};

// Line-by-line view of the text with the same line numbering as tinyobjloader (\n or \r\n endings).
template <class F>
void for_each_line(std::string_view text, F&& f) {
  std::size_t line = 0, at = 0;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view l = text.substr(at, end - at);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    ++line;
    if (!f(line, l)) return;
    at = end + 1;
  }
}

std::string_view skip_blanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return s;
}

std::string_view keyword(std::string_view l) {
  l = skip_blanks(l);
  std::size_t n = 0;
  while (n < l.size() && l[n] != ' ' && l[n] != '\t') ++n;
  return l.substr(0, n);
}

// The first face that references a missing vertex or normal, uses index 0, or has under 3 corners.
std::optional<Problem> find_bad_face(std::string_view text) {
  std::size_t v_total = 0, vn_total = 0, vt_total = 0;
  for_each_line(text, [&](std::size_t, std::string_view l) {
    std::string_view k = keyword(l);
    v_total += k == "v", vn_total += k == "vn", vt_total += k == "vt";
    return true;
  });
  std::optional<Problem> found;
  std::size_t v_seen = 0, vn_seen = 0, vt_seen = 0;
  for_each_line(text, [&](std::size_t line, std::string_view l) {
    std::string_view k = keyword(l);
    v_seen += k == "v", vn_seen += k == "vn", vt_seen += k == "vt";
    if (k != "f") return true;
    std::string_view rest = skip_blanks(l).substr(1);
    int corners = 0;
    while (!(rest = skip_blanks(rest)).empty()) {
      std::size_t n = rest.find_first_of(" \t");
      std::string_view corner = rest.substr(0, n);
      rest = n == std::string_view::npos ? std::string_view() : rest.substr(n);
      if (corner.front() == '#') break;
      ++corners;
      // v, v/vt, v//vn, v/vt/vn: slot 0 positions, 1 texture coordinates, 2 normals.
      const char* names[3] = {"vertex", "texture coordinate", "normal"};
      const char* keys[3] = {"v", "vt", "vn"};
      const std::size_t totals[3] = {v_total, vt_total, vn_total}, seen[3] = {v_seen, vt_seen, vn_seen};
      for (int slot = 0; slot < 3 && !corner.empty(); ++slot) {
        std::size_t slash = corner.find('/');
        std::string_view num = corner.substr(0, slash);
        corner = slash == std::string_view::npos ? std::string_view() : corner.substr(slash + 1);
        if (num.empty()) {
          if (slot == 0) found = Problem{line, "face corner without a vertex index (write 'f v1 v2 v3')"};
          if (found) return false;
          continue;
        }
        long long idx = 0;
        auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), idx);
        if (ec == std::errc::result_out_of_range) {
          found = Problem{line, fmt::format("{} index '{}' in a face is past 64 bits (no file has that many; fix the "
                                            "face)", names[slot], num)};
          return false;
        }
        if (ec != std::errc() || end != num.data() + num.size()) {
          found = Problem{line, fmt::format("bad {} index '{}' in a face (indices are integers)", names[slot], num)};
          return false;
        }
        if (idx == 0) {
          found = Problem{line, fmt::format("{} index 0 in a face (OBJ indices start at 1)", names[slot])};
          return false;
        }
        // Positive indices may point anywhere in the file; negative ones count back from this line.
        long long resolved = idx > 0 ? idx : static_cast<long long>(seen[slot]) + idx + 1;
        long long limit = idx > 0 ? static_cast<long long>(totals[slot]) : static_cast<long long>(seen[slot]);
        if (resolved < 1 || resolved > limit) {
          found = Problem{line, fmt::format("face {} index {} out of range (the file has {} '{}' lines{}; fix or "
                                            "remove the face)",
                                            names[slot], idx, limit, keys[slot], idx > 0 ? "" : " before this one")};
          return false;
        }
      }
    }
    if (corners < 3) {
      found = Problem{line, fmt::format("face with {} corner{} (a face needs at least 3 vertices)", corners,
                                        corners == 1 ? "" : "s")};
      return false;
    }
    return true;
  });
  return found;
}

// The first coordinate of a "v", "vn" or "vt" line that is not a finite number a float holds.
// tinyobjloader reads "NaN" and other words as 0 (so `v NaN 2 0` hashed like `v 0 2 0`) and 1e39 as inf.
std::optional<Problem> find_bad_number(std::string_view text) {
  std::optional<Problem> found;
  for_each_line(text, [&](std::size_t line, std::string_view l) {
    const std::string_view k = keyword(l);
    if (k != "v" && k != "vn" && k != "vt") return true;
    std::string_view rest = skip_blanks(l).substr(k.size());
    while (!(rest = skip_blanks(rest)).empty() && rest.front() != '#') {
      const std::size_t n = std::min(rest.find_first_of(" \t"), rest.size());
      const std::string_view token = rest.substr(0, n);
      rest.remove_prefix(n);
      const std::string_view digits = token.front() == '+' ? token.substr(1) : token;  // from_chars takes no '+'
      double v = 0;
      auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
      if (ec == std::errc() && end == digits.data() + digits.size() && std::isfinite(v) &&
          std::fabs(v) <= std::numeric_limits<float>::max())
        continue;
      found = Problem{line, fmt::format("'{}' in a '{}' line is not a finite number a float holds (|x| <= {:.4g}; fix "
                                        "the number)",
                                        token, k, std::numeric_limits<float>::max())};
      return false;
    }
    return true;
  });
  return found;
}

// The line of the `ordinal`-th (0-based) statement `key` ("v", "vn").
std::size_t line_of(std::string_view text, std::string_view key, std::size_t ordinal) {
  std::size_t found = 0, count = 0;
  for_each_line(text, [&](std::size_t line, std::string_view l) {
    if (keyword(l) != key) return true;
    if (count++ == ordinal) found = line;
    return found == 0;
  });
  return found;
}

std::size_t line_count(std::string_view text) {
  std::size_t n = 0;
  for_each_line(text, [&](std::size_t, std::string_view) { return ++n, true; });
  return n;
}

// The first line number tinyobjloader's message mentions ("line 12", "line: 12"), or 0.
std::size_t line_in_message(std::string_view msg) {
  for (std::size_t at = msg.find("line"); at != std::string_view::npos; at = msg.find("line", at + 4)) {
    std::size_t p = at + 4;
    while (p < msg.size() && (msg[p] == ' ' || msg[p] == ':')) ++p;
    std::size_t n = 0;
    auto [end, ec] = std::from_chars(msg.data() + p, msg.data() + msg.size(), n);
    if (ec == std::errc() && n > 0) return n;
  }
  return 0;
}

}  // namespace

Scene load_obj(const std::filesystem::path& path, const std::string& display, const LoadOptions& options) {
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) fail(fmt::format("{}: error: cannot open (check the path)", display));
  // Peak memory is about 10x the file: the text itself (1x); tinyobjloader's arrays, worst for minimal
  // "f 1 2 3" lines (8 bytes of text -> 3 x 12-byte index_t + per-face count, material and smoothing ids =
  // 45 bytes, 5.6x); our de-indexed copy with its remap tables (minimal "v 0 0 0" lines: 8 bytes of text ->
  // 24 bytes of position + normal + 12 bytes of remap, 4.5x, but those files have few faces). Typical
  // files ("v -1.234567 ..." / "f 12//12 ...") stay below 5x.
  check_memory(display, file_size * 10, memory_limit(options),
               fmt::format("estimated as 10x the {} file", format_bytes(file_size)));
  std::optional<std::string> text = util::read_file(path);
  if (!text) fail(fmt::format("{}: error: cannot open (check the path and permissions)", display));

  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // From a string with an empty material text: AO needs no materials, and mtllib files are not read.
  bool ok = reader.ParseFromString(*text, "", config);
  const std::string& err = reader.Error();
  const std::string& warn = reader.Warning();
  const bool out_of_bounds = warn.find("out of bounds") != std::string::npos;
  auto fail_at = [&](std::size_t line, const std::string& what) -> void {
    if (line == 0) fail(fmt::format("{}: error: {}", display, what));
    fail(fmt::format("{}:{}: error: {}", display, line, what));
  };
  if (!ok || !err.empty() || out_of_bounds) {
    if (auto p = find_bad_face(*text)) fail_at(p->line, p->what);
    std::string msg = one_line(!err.empty() ? err : warn);
    fail_at(line_in_message(msg),
            fmt::format("{} (fix the file; tinyobjloader could not read it)", msg.empty() ? "unreadable OBJ" : msg));
  }

  // Checked on every file, not only when tinyobjloader complains: it reads a NaN coordinate as 0 and wraps a
  // face index past 64 bits, and says nothing.
  if (auto p = find_bad_number(*text)) fail_at(p->line, p->what);
  if (auto p = find_bad_face(*text)) fail_at(p->line, p->what);

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const std::vector<tinyobj::shape_t>& shapes = reader.GetShapes();
  const std::size_t n_pos = attrib.vertices.size() / 3, n_nrm = attrib.normals.size() / 3;
  std::size_t corners = 0;
  for (const tinyobj::shape_t& s : shapes) corners += s.mesh.indices.size();
  if (corners == 0)
    fail_at(
        std::max<std::size_t>(1, line_count(*text)),
        fmt::format("no triangles in the file ({} vertices, no faces with 3 or more corners; add 'f' lines)", n_pos));
  for (const tinyobj::shape_t& s : shapes)
    for (const tinyobj::index_t& i : s.mesh.indices)
      if (i.vertex_index < 0 || static_cast<std::size_t>(i.vertex_index) >= n_pos ||
          static_cast<std::size_t>(i.normal_index + 1) > n_nrm) {
        auto p = find_bad_face(*text);
        fail_at(p ? p->line : 0, p ? p->what : "a face index is out of range (fix the faces)");
      }
  for (std::size_t v = 0; v < n_pos; ++v)
    if (!std::isfinite(attrib.vertices[3 * v]) || !std::isfinite(attrib.vertices[3 * v + 1]) ||
        !std::isfinite(attrib.vertices[3 * v + 2]))
      fail_at(line_of(*text, "v", v), "non-finite vertex coordinate (fix the number)");
  // Distinct vertices are at most one per corner, and at most positions x (normals + 1) when every corner
  // has a normal (computed ones split at creases, up to one vertex per corner).
  const bool all_normals = n_nrm > 0 && std::all_of(shapes.begin(), shapes.end(), [](const tinyobj::shape_t& s) {
    return std::all_of(s.mesh.indices.begin(), s.mesh.indices.end(),
                       [](const tinyobj::index_t& i) { return i.normal_index >= 0; });
  });
  check_size(display, all_normals ? std::min<std::uint64_t>(corners, std::uint64_t{n_pos} * (n_nrm + 1)) : corners,
             corners, options);
  text.reset();  // only messages needed it; keep it out of the peak

  Scene scene;
  scene.mesh_count = static_cast<int>(
      std::count_if(shapes.begin(), shapes.end(), [](const tinyobj::shape_t& s) { return !s.mesh.indices.empty(); }));
  scene.indices.reserve(corners);
  // Vertex per (position, normal) pair: a chain of the vertices made from each position, as OBJ files
  // pair a position with one or a few normals (hard edges), so chains stay short.
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> head(n_pos, kNone), next, position_of;
  std::vector<int> normal_of;
  bool need_smooth = false;
  for (const tinyobj::shape_t& s : shapes) {
    for (const tinyobj::index_t& i : s.mesh.indices) {
      const std::uint32_t p = static_cast<std::uint32_t>(i.vertex_index);
      std::uint32_t v = head[p];
      while (v != kNone && normal_of[v] != i.normal_index) v = next[v];
      if (v == kNone) {
        v = static_cast<std::uint32_t>(scene.positions.size());
        scene.positions.emplace_back(attrib.vertices[3 * p], attrib.vertices[3 * p + 1], attrib.vertices[3 * p + 2]);
        glm::vec3 n(0.0f);
        if (i.normal_index >= 0) {
          const float* f = &attrib.normals[3 * static_cast<std::size_t>(i.normal_index)];
          n = safe_normalize({f[0], f[1], f[2]}, glm::vec3(0.0f));
        }
        need_smooth |= n == glm::vec3(0.0f);  // absent, zero or broken normal
        scene.normals.push_back(n);
        next.push_back(head[p]);
        head[p] = v;
        position_of.push_back(p);
        normal_of.push_back(i.normal_index);
      }
      scene.indices.push_back(v);
    }
  }
  if (need_smooth) {
    // By position index, so faces sharing a position (but not a normal) blend, unless a crease parts them.
    std::vector<std::uint32_t> by_position(scene.indices.size());
    for (std::size_t k = 0; k < scene.indices.size(); ++k) by_position[k] = position_of[scene.indices[k]];
    std::vector<glm::vec3> positions(n_pos);
    for (std::size_t p = 0; p < n_pos; ++p)
      positions[p] = {attrib.vertices[3 * p], attrib.vertices[3 * p + 1], attrib.vertices[3 * p + 2]};
    assign_corner_normals(scene, 0, 0, crease_normals(positions, by_position));
  }
  return scene;
}

}  // namespace aovar::scene::detail
