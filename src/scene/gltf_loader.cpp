// glTF 2.0 (.gltf text, .glb binary) through tinygltf: the default scene's node tree is walked with node
// transforms (matrix or TRS) applied to positions and normals (inverse transpose; winding flipped under
// mirroring transforms), and every triangle primitive instance is merged. Images are not decoded (AO needs
// no textures). The container and the JSON are checked here first so that broken files get a byte offset.
#include <cstring>
#include <optional>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "scene/detail.h"
#include "scene/gltf_resources.h"
#include "util/fs.h"

namespace aovar::scene::detail {
namespace {

using Model = tinygltf::Model;

// Validates the JSON text without building a document; on error gives the byte offset and message.
struct JsonCheck : nlohmann::json_sax<nlohmann::json> {
  std::size_t position = 0;
  std::string message;
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return true; }
  bool key(string_t&) override { return true; }
  bool end_object() override { return true; }
  bool start_array(std::size_t) override { return true; }
  bool end_array() override { return true; }
  bool parse_error(std::size_t pos, const std::string&, const nlohmann::detail::exception& ex) override {
    position = pos;
    message = ex.what();
    if (auto close = message.find("] "); message.starts_with("[json.") && close != std::string::npos)
      message.erase(0, close + 2);  // drop "[json.exception.parse_error.101] "
    return false;
  }
};

void check_json(const std::string& display, std::string_view json, std::size_t base) {
  JsonCheck check;
  if (nlohmann::json::sax_parse(json.begin(), json.end(), &check)) return;
  fail(fmt::format("{}: offset {}: error: invalid JSON: {} (the file is truncated or not glTF 2.0 JSON)", display,
                   base + (check.position > 0 ? check.position - 1 : 0), check.message));
}

std::uint32_t u32_at(std::string_view b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);  // glTF binaries are little-endian, as is every supported host
  return v;
}

// GLB container: 12-byte header, then a JSON chunk. Returns the file offset of the BIN chunk's data.
std::optional<std::size_t> check_glb(const std::string& display, std::string_view bytes) {
  auto bad = [&](std::size_t offset, const std::string& what) {
    fail(fmt::format("{}: offset {}: error: {}", display, offset, what));
  };
  if (bytes.size() < 12)
    bad(0, fmt::format("{} bytes is too short for a glTF binary header (12 bytes; the file "
                       "is truncated or not a .glb)",
                       bytes.size()));
  if (bytes.substr(0, 4) != "glTF")
    bad(0, "not a glTF binary: the file does not start with 'glTF' (a text glTF must be named .gltf)");
  if (u32_at(bytes, 4) != 2)
    bad(4, fmt::format("glTF binary version {} (only version 2 is supported)", u32_at(bytes, 4)));
  if (u32_at(bytes, 8) > bytes.size())
    bad(8, fmt::format("the header says {} bytes but the file has {} (the file is truncated)", u32_at(bytes, 8),
                       bytes.size()));
  if (bytes.size() < 20) bad(12, "no JSON chunk after the header (the file is truncated)");
  std::uint64_t json_len = u32_at(bytes, 12);
  if (bytes.substr(16, 4) != "JSON") bad(16, "the first chunk is not JSON (the file is corrupt)");
  if (20 + json_len > bytes.size())
    bad(12, fmt::format("the JSON chunk ({} bytes) runs past the end of the file "
                        "(the file is truncated)",
                        json_len));
  check_json(display, bytes.substr(20, json_len), 20);
  std::size_t bin = 20 + ((json_len + 3) & ~std::uint64_t{3});
  if (bin + 8 <= bytes.size() && bytes.substr(bin + 4, 4) == std::string_view("BIN\0", 4)) return bin + 8;
  return std::nullopt;
}

bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

glm::mat4 local_matrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    glm::mat4 m;
    for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = static_cast<float>(n.matrix[i]);  // column-major, as glm
    return m;
  }
  glm::mat4 m(1.0f);
  if (n.translation.size() == 3) m = glm::translate(m, glm::vec3(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4) {  // glTF stores x, y, z, w; glm's constructor takes w first
    const auto& r = n.rotation;
    m *= glm::mat4(glm::mat4_cast(glm::normalize(glm::dquat(r[3], r[0], r[1], r[2]))));
  }
  if (n.scale.size() == 3) m = glm::scale(m, glm::vec3(n.scale[0], n.scale[1], n.scale[2]));
  return m;
}

struct Instance {
  int mesh;
  glm::mat4 world;
};

// What a node (or the whole scene) expands to; sums saturate instead of wrapping.
struct Expansion {
  std::uint64_t instances = 0, vertices = 0, indices = 0;
  Expansion& operator+=(const Expansion& o) {
    auto add = [](std::uint64_t a, std::uint64_t b) { return b > UINT64_MAX - a ? UINT64_MAX : a + b; };
    instances = add(instances, o.instances), vertices = add(vertices, o.vertices), indices = add(indices, o.indices);
    return *this;
  }
};
// More mesh instances than any real scene places (Sponza has 1, the Bistro ~3,000); each costs a world
// matrix and its copy of the mesh, and check_size bounds the triangles separately.
inline constexpr std::uint64_t kMaxInstances = 1'000'000;

// A typed, bounds-checked view of an accessor's elements.
struct Stream {
  const unsigned char* data = nullptr;
  std::size_t stride = 0, count = 0;
  int component = 0, components = 0;
  bool normalized = false;

  float get(std::size_t i, int c) const {
    const unsigned char* p = data + i * stride;
    switch (component) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p + 4 * c, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        auto v = static_cast<std::int8_t>(p[c]);
        return normalized ? std::max(v / 127.0f, -1.0f) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? p[c] / 255.0f : p[c];
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, p + 2 * c, 2);
        return normalized ? std::max(v / 32767.0f, -1.0f) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p + 2 * c, 2);
        return normalized ? v / 65535.0f : v;
      }
      default:
        return 0.0f;
    }
  }
  std::uint32_t index(std::size_t i) const {
    const unsigned char* p = data + i * stride;
    switch (component) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return p[0];
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      default: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
    }
  }
};

class Loader {
 public:
  Loader(const Model& m, const std::string& display, std::optional<std::size_t> bin)
      : m_(m), display_(display), bin_(bin) {}

  // The default scene's root nodes (every node that is nobody's child when the file has no scenes).
  std::vector<int> roots() const {
    int scene = m_.defaultScene >= 0 ? m_.defaultScene : (m_.scenes.empty() ? -1 : 0);
    if (scene >= static_cast<int>(m_.scenes.size())) error(fmt::format("default scene {} does not exist", scene));
    if (scene >= 0) return m_.scenes[scene].nodes;
    std::vector<char> child(m_.nodes.size(), 0);
    for (const tinygltf::Node& n : m_.nodes)
      for (int c : n.children)
        if (c >= 0 && c < static_cast<int>(child.size())) child[c] = 1;
    std::vector<int> out;
    for (std::size_t i = 0; i < child.size(); ++i)
      if (!child[i]) out.push_back(static_cast<int>(i));
    return out;
  }

  // Mesh instances, vertices and indices the roots expand to, counted on the node graph before anything is
  // built: nodes that share children multiply (2^N instances from N nodes), so the expansion itself must not
  // be the check. Iterative post-order walk (a deep chain must not overflow the stack); a node met again
  // while still on the path is a cycle. Sums saturate at UINT64_MAX, which every limit refuses.
  Expansion count(const std::vector<int>& roots) {
    enum : char { kNew, kOnPath, kDone };
    std::vector<char> state(m_.nodes.size(), kNew);
    std::vector<Expansion> below(m_.nodes.size());
    std::vector<std::pair<int, std::size_t>> path;  // node, next child to visit
    Expansion total;
    for (int root : roots) {
      check_node(root, -1);
      if (state[root] == kNew) state[root] = kOnPath, path.push_back({root, 0});
      while (!path.empty()) {
        auto& [node, next] = path.back();
        const tinygltf::Node& n = m_.nodes[node];
        if (next < n.children.size()) {
          int c = n.children[next++];
          check_node(c, node);
          if (state[c] == kOnPath)
            error(fmt::format("node {} is its own ancestor (the node tree has a cycle through node {})", c, node));
          if (state[c] == kNew) state[c] = kOnPath, path.push_back({c, 0});
          continue;
        }
        Expansion e = n.mesh >= 0 ? mesh_size(node, n.mesh) : Expansion{};
        for (int c : n.children) e += below[c];
        below[node] = e;
        state[node] = kDone;
        path.pop_back();
      }
      total += below[root];
    }
    if (total.instances > kMaxInstances)
      error(fmt::format("the node graph expands to {} mesh instances, more than aovar builds ({})",
                        total.instances == UINT64_MAX ? std::string("over 2^64") : std::to_string(total.instances),
                        kMaxInstances),
            "nodes that share children multiply; give each node one parent");
    return total;
  }

  // Every mesh instance with its world matrix, depth first in glTF order; only called after `count` has
  // proved the graph acyclic and the expansion within limits.
  std::vector<Instance> instances(const std::vector<int>& roots) const {
    std::vector<Instance> out;
    std::vector<std::pair<int, glm::mat4>> todo;  // node, its parent's world matrix
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) todo.push_back({*r, glm::mat4(1.0f)});
    while (!todo.empty()) {
      auto [node, parent] = todo.back();
      todo.pop_back();
      const tinygltf::Node& n = m_.nodes[node];
      const glm::mat4 world = parent * local_matrix(n);
      if (n.mesh >= 0) out.push_back({n.mesh, world});
      for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) todo.push_back({*c, world});
    }
    return out;
  }

  void emit(const Instance& in, Scene& s) {
    const tinygltf::Mesh& mesh = m_.meshes[in.mesh];
    const glm::mat3 linear(in.world);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
    const bool mirrored = glm::determinant(linear) < 0.0f;
    for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const tinygltf::Primitive& p = mesh.primitives[pi];
      if (!triangles(p)) continue;  // points and lines have no surface to occlude
      where_ = fmt::format("mesh {}{} primitive {}", in.mesh, mesh.name.empty() ? "" : " '" + mesh.name + "'", pi);
      auto pos_it = p.attributes.find("POSITION");
      if (pos_it == p.attributes.end()) error(where_ + " has no POSITION attribute", "add vertex positions");
      Stream pos = stream(pos_it->second, "POSITION", TINYGLTF_TYPE_VEC3);
      std::optional<Stream> nrm;
      if (auto it = p.attributes.find("NORMAL"); it != p.attributes.end()) {
        nrm = stream(it->second, "NORMAL", TINYGLTF_TYPE_VEC3);
        if (nrm->count != pos.count)
          error(fmt::format("{}: NORMAL has {} elements but POSITION has {}", where_, nrm->count, pos.count));
      }
      std::vector<std::uint32_t> corners;
      if (p.indices >= 0) {
        Stream idx = stream(p.indices, "indices", TINYGLTF_TYPE_SCALAR);
        if (idx.component != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            idx.component != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            idx.component != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
          error(where_ + ": indices must be unsigned byte, short or int");
        corners.resize(idx.count);
        for (std::size_t i = 0; i < idx.count; ++i) {
          corners[i] = idx.index(i);
          if (corners[i] >= pos.count)
            error(fmt::format("{}: index {} is {} but there are {} vertices", where_, i, corners[i], pos.count),
                  "the file is corrupt");
        }
      } else {
        corners.resize(pos.count);
        for (std::size_t i = 0; i < pos.count; ++i) corners[i] = static_cast<std::uint32_t>(i);
      }
      std::vector<std::uint32_t> tris = to_list(p.mode, corners);
      if (mirrored)
        for (std::size_t i = 0; i + 2 < tris.size(); i += 3) std::swap(tris[i + 1], tris[i + 2]);

      const std::uint32_t base = static_cast<std::uint32_t>(s.positions.size());
      for (std::size_t i = 0; i < pos.count; ++i)
        s.positions.push_back(glm::vec3(in.world * glm::vec4(pos.get(i, 0), pos.get(i, 1), pos.get(i, 2), 1.0f)));
      if (nrm) {
        for (std::size_t i = 0; i < pos.count; ++i) {
          glm::vec3 n = normal_matrix * glm::vec3(nrm->get(i, 0), nrm->get(i, 1), nrm->get(i, 2));
          s.normals.push_back(safe_normalize(n, glm::vec3(0.0f)));
        }
      }
      // Crease-aware smooth normals (per vertex index) where the file has none, computed in world space.
      // (The glTF spec asks for flat normals there; smooth ones suit AO on scanned meshes, and the crease
      // keeps a box's faces flat.) Zero or broken normals from the file get the same treatment; vertices
      // whose corners part at a crease are copied after the primitive's own.
      if (!nrm) s.normals.resize(s.positions.size(), glm::vec3(0.0f));
      const bool need = std::any_of(s.normals.begin() + base, s.normals.end(),
                                    [](const glm::vec3& n) { return n == glm::vec3(0.0f); });
      const std::size_t first_index = s.indices.size();
      for (std::uint32_t t : tris) s.indices.push_back(base + t);
      if (need) {
        std::span<const glm::vec3> world(s.positions.data() + base, pos.count);
        assign_corner_normals(s, base, first_index, crease_normals(world, tris));
      }
      ++s.mesh_count;
    }
  }

 private:
  static bool triangles(const tinygltf::Primitive& p) {
    return p.mode < 0 || p.mode == TINYGLTF_MODE_TRIANGLES || p.mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           p.mode == TINYGLTF_MODE_TRIANGLE_FAN;
  }

  static std::vector<std::uint32_t> to_list(int mode, std::vector<std::uint32_t>& c) {
    if (mode < 0 || mode == TINYGLTF_MODE_TRIANGLES) {
      c.resize(c.size() / 3 * 3);
      return std::move(c);
    }
    std::vector<std::uint32_t> out;
    for (std::size_t i = 2; i < c.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
        out.insert(out.end(), {c[0], c[i - 1], c[i]});
      else if (i % 2 == 0)
        out.insert(out.end(), {c[i - 2], c[i - 1], c[i]});
      else
        out.insert(out.end(), {c[i - 1], c[i - 2], c[i]});  // odd strip triangles keep the winding
    }
    return out;
  }

  [[noreturn]] void error(const std::string& what, const std::string& todo = "the file is not valid glTF 2.0",
                          std::optional<std::size_t> offset = std::nullopt) const {
    if (offset) fail(fmt::format("{}: offset {}: error: {} ({})", display_, *offset, what, todo));
    fail(fmt::format("{}: error: {} ({})", display_, what, todo));
  }

  void check_node(int node, int parent) const {
    if (node >= 0 && node < static_cast<int>(m_.nodes.size())) return;
    if (parent < 0) error(fmt::format("the scene's root node {} does not exist", node));
    error(fmt::format("node {} has child {}, which does not exist", parent, node));
  }

  // Vertices and indices one instance of `mesh` adds (triangle primitives only); memoised per mesh.
  Expansion mesh_size(int node, int mesh) {
    if (mesh >= static_cast<int>(m_.meshes.size()))
      error(fmt::format("node {} uses mesh {}, which does not exist", node, mesh));
    if (mesh_sizes_.empty()) mesh_sizes_.resize(m_.meshes.size());
    std::optional<Expansion>& memo = mesh_sizes_[mesh];
    if (memo) return *memo;
    Expansion e{1, 0, 0};
    for (const tinygltf::Primitive& p : m_.meshes[mesh].primitives) {
      auto pos = p.attributes.find("POSITION");
      if (!triangles(p) || pos == p.attributes.end()) continue;
      std::uint64_t n = accessor(pos->second, "POSITION").count;
      std::uint64_t corners = p.indices >= 0 ? accessor(p.indices, "indices").count : n;
      // Without NORMAL, computed normals may copy vertices at creases: up to one per corner.
      e.vertices += p.attributes.count("NORMAL") ? n : std::max(n, corners);
      e.indices +=
          p.mode == TINYGLTF_MODE_TRIANGLES || p.mode < 0 ? corners : 3 * (std::max<std::uint64_t>(corners, 2) - 2);
    }
    return *(memo = e);
  }

  const tinygltf::Accessor& accessor(int index, const char* what) const {
    if (index < 0 || index >= static_cast<int>(m_.accessors.size()))
      error(fmt::format("{}{}{} refers to accessor {}, which does not exist", where_, where_.empty() ? "" : " ", what,
                        index));
    return m_.accessors[index];
  }

  Stream stream(int index, const char* what, int type) const {
    const tinygltf::Accessor& a = accessor(index, what);
    const std::string label = fmt::format("{} {} (accessor {})", where_, what, index);
    if (a.type != type) error(label + " has the wrong element type (POSITION and NORMAL are VEC3, indices SCALAR)");
    if (a.sparse.isSparse) error(label + " is a sparse accessor", "sparse accessors are not supported; densify it");
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(m_.bufferViews.size()))
      error(label + " has no buffer view", "accessors without data are not supported");
    const tinygltf::BufferView& v = m_.bufferViews[a.bufferView];
    if (v.buffer < 0 || v.buffer >= static_cast<int>(m_.buffers.size()))
      error(fmt::format("{}: buffer view {} refers to buffer {}, which does not exist", label, a.bufferView, v.buffer));
    const std::vector<unsigned char>& data = m_.buffers[v.buffer].data;
    const int elem = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType)) *
                     tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    const int stride = a.ByteStride(v);
    if (elem <= 0 || stride <= 0) error(label + " has an invalid component type or byte stride");
    if (type == TINYGLTF_TYPE_VEC3 &&
        (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT || a.componentType == TINYGLTF_COMPONENT_TYPE_INT ||
         a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE))
      error(label + " has an unsupported component type (use float)");
    const std::uint64_t start = std::uint64_t{v.byteOffset} + a.byteOffset;
    const std::uint64_t end =
        a.count == 0 ? start : start + std::uint64_t{static_cast<unsigned>(stride)} * (a.count - 1) + elem;
    if (end > std::uint64_t{v.byteOffset} + v.byteLength || end > data.size()) {
      std::optional<std::size_t> at;
      if (bin_ && v.buffer == 0 && m_.buffers[0].uri.empty()) at = *bin_ + start;
      error(fmt::format("{} reads bytes {}..{} of buffer {}, which has {} (view ends at {})", label, start, end,
                        v.buffer, data.size(), v.byteOffset + v.byteLength),
            "the file is truncated or corrupt", at);
    }
    return Stream{data.data() + start,
                  static_cast<std::size_t>(stride),
                  a.count,
                  a.componentType,
                  tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)),
                  a.normalized};
  }

  const Model& m_;
  const std::string& display_;
  std::optional<std::size_t> bin_;
  std::string where_;
  std::vector<std::optional<Expansion>> mesh_sizes_;
};

}  // namespace

Scene load_gltf(const std::filesystem::path& path, const std::string& display, const LoadOptions& options,
                bool binary) {
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) fail(fmt::format("{}: error: cannot open (check the path)", display));
  // Peak while parsing is about 4x the file: the bytes read (1x), tinygltf's copy of the buffers (1x; for
  // base64 data URIs the decoded 0.75x plus the JSON string 1x), and our output (positions + normals as
  // float3 plus u32 indices: at most ~2x typical float3/u16 input). Instancing can multiply the output; that
  // is checked exactly once the node tree is known.
  check_memory(display, file_size * 4, memory_limit(options),
               fmt::format("estimated as 4x the {} file", format_bytes(file_size)));
  if (file_size > 0xffffffffu) fail(fmt::format("{}: error: glTF files over 4 GiB are not supported", display));
  std::optional<std::string> bytes = util::read_file(path);
  if (!bytes) fail(fmt::format("{}: error: cannot open (check the path and permissions)", display));
  if (bytes->empty()) fail(fmt::format("{}: offset 0: error: the file is empty (export the scene again)", display));

  std::optional<std::size_t> bin;
  if (binary)
    bin = check_glb(display, *bytes);
  else
    check_json(display, *bytes, 0);

  // The files it names: the path policy and their sizes, before tinygltf reads any (through `access`).
  const std::uint64_t limit = memory_limit(options), own = file_size * 4;
  const std::string_view json = binary ? std::string_view(*bytes).substr(20, u32_at(*bytes, 12)) : std::string_view(*bytes);
  ResourceAccess access = check_resources(path, display, resource_refs(json), limit > own ? limit - own : 0);

  tinygltf::TinyGLTF gltf;
  gltf.SetFsCallbacks(fs_callbacks(access));
  gltf.SetImageLoader(&skip_image, nullptr);
  Model model;
  std::string err, warn;
  const std::string base_dir = path.parent_path().string();
  const auto size = static_cast<unsigned int>(bytes->size());
  bool ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, &warn,
                                               reinterpret_cast<const unsigned char*>(bytes->data()), size, base_dir)
                   : gltf.LoadASCIIFromString(&model, &err, &warn, bytes->data(), size, base_dir);
  bytes.reset();
  if (!access.error.empty()) fail(fmt::format("{}: error: cannot read a buffer: {}", display, access.error));
  if (!ok || !err.empty())
    fail(fmt::format("{}: error: {} (check that the file is valid glTF 2.0 and its buffers exist)", display,
                     err.empty() ? "tinygltf could not load the file" : one_line(err)));

  Loader loader(model, display, bin);
  const std::vector<int> roots = loader.roots();
  const Expansion expansion = loader.count(roots);
  check_size(display, expansion.vertices, expansion.indices, options);
  std::vector<Instance> instances = loader.instances(roots);
  Scene scene;
  scene.positions.reserve(expansion.vertices);
  scene.normals.reserve(expansion.vertices);
  scene.indices.reserve(expansion.indices);
  for (const Instance& in : instances) loader.emit(in, scene);
  if (scene.indices.empty())
    fail(
        fmt::format("{}: error: no triangles in the default scene ({} mesh instance{}; add triangle meshes to the "
                    "scene's nodes)",
                    display, instances.size(), instances.size() == 1 ? "" : "s"));
  return scene;
}

}  // namespace aovar::scene::detail
