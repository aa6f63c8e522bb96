#include "scene/gltf_resources.h"

#include <sys/stat.h>

#include <algorithm>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "scene/detail.h"
#include "scene/resource_path.h"
#include "util/fs.h"
#include "util/path_names.h"

namespace aovar::scene::detail {
namespace fs = std::filesystem;

std::string ResourceRef::label() const {
  return fmt::format("{} {} '{}'", image ? "image" : "buffer", index, util::printable_name(uri));
}

namespace {

// Collects buffers[i].uri / byteLength and images[i].uri without building a document (a .gltf may hold
// hundreds of MiB of base64 data URIs). Depth 1 is the root object, 2 the arrays, 3 their elements. Only an
// element that is an object has a ref: an array there (`"images": [["uri", ...]]`, malformed) holds values
// at depth 3 too, which must not reach refs.back() (a fuzz finding: back() of an empty vector).
struct RefCollector : nlohmann::json_sax<nlohmann::json> {
  std::vector<ResourceRef> refs;
  int depth = 0;
  std::string top, field;  // the root's current key; the element's current key
  std::size_t count[2] = {0, 0};
  bool element_open = false;  // depth 3 is an object element of buffers or images, refs.back() its ref

  bool in_element() const { return depth == 3 && element_open; }
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t v) override {
    if (in_element() && field == "byteLength" && v >= 0) refs.back().byte_length = static_cast<std::uint64_t>(v);
    return true;
  }
  bool number_unsigned(number_unsigned_t v) override {
    if (in_element() && field == "byteLength") refs.back().byte_length = v;
    return true;
  }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t& s) override {
    if (in_element() && field == "uri" && !is_data_uri(s)) refs.back().uri = s;
    return true;
  }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override {
    if (++depth == 3 && (top == "buffers" || top == "images")) {
      const bool image = top == "images";
      refs.push_back({image, count[image]++, {}, {}});
      field.clear();
      element_open = true;
    }
    return true;
  }
  bool key(string_t& k) override {
    if (depth == 1) top = k;
    if (depth == 3) field = k;
    return true;
  }
  bool end_object() override {
    if (depth-- == 3) element_open = false;
    return true;
  }
  bool start_array(std::size_t) override { return ++depth, true; }
  bool end_array() override { return --depth, true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
};

}  // namespace

std::vector<ResourceRef> resource_refs(std::string_view json) {
  RefCollector c;
  nlohmann::json::sax_parse(json.begin(), json.end(), &c);
  std::erase_if(c.refs, [](const ResourceRef& r) { return r.uri.empty(); });
  return c.refs;
}

ResourceAccess check_resources(const fs::path& scene_file, const std::string& display,
                               const std::vector<ResourceRef>& refs, std::uint64_t limit) {
  ResourceAccess access;
  access.max_bytes = limit;
  std::uint64_t left = limit;
  for (const ResourceRef& r : refs) {
    const fs::path file = resolve_resource(scene_file, display, r.image ? fmt::format("image {}", r.index)
                                                                        : fmt::format("buffer {}", r.index), r.uri);
    if (r.image) continue;  // never read: FileExists says no, and tinygltf only warns for an image
    auto too_large = [&](std::uint64_t bytes, const char* what) {
      fail(fmt::format("{}: error: {}: {} {}, more than the {} left for the scene's buffers (use a smaller or "
                       "decimated scene, or free memory: the limit is half of the available memory)",
                       display, r.label(), what, format_bytes(bytes), format_bytes(left)));
    };
    // Both before a byte is read: tinygltf would allocate the file's size, and then compare it with byteLength.
    const std::uint64_t declared = r.byte_length.value_or(0);
    if (declared > left) too_large(declared, "declares a byteLength of");
    struct stat st {};
    const std::uint64_t actual =
        ::stat(file.c_str(), &st) == 0 && S_ISREG(st.st_mode) ? static_cast<std::uint64_t>(st.st_size) : 0;
    if (actual > left) too_large(actual, "is a file of");
    left -= std::max(declared, actual);
    access.files.insert(file);
  }
  return access;
}

namespace {

ResourceAccess& access_of(void* user) { return *static_cast<ResourceAccess*>(user); }

bool allowed(const std::string& path, void* user) {
  return access_of(user).files.count(fs::path(path).lexically_normal()) > 0;
}

std::string expand(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion, ever

bool read_whole(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  ResourceAccess& access = access_of(user);
  auto refuse = [&](const std::string& why) {
    if (access.error.empty()) access.error = why;
    if (err) *err = why;
    return false;
  };
  if (!allowed(path, user)) return refuse(fmt::format("{}: not a buffer the scene names", path));
  try {  // tinygltf is C code at heart: nothing may be thrown through it
    const std::optional<std::string> bytes = util::read_file(path, access.max_bytes);
    if (!bytes) return refuse(fmt::format("{}: cannot open (check the path and permissions)", util::display_path(path)));
    out->assign(bytes->begin(), bytes->end());
    return true;
  } catch (const util::ReadError& e) {
    return refuse(fmt::format("{}: {}", util::display_path(path), e.reason));
  } catch (const std::bad_alloc&) {
    return refuse(fmt::format("{}: out of memory reading it", util::display_path(path)));
  }
}

bool write_whole(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "aovar never writes glTF files";
  return false;
}

}  // namespace

tinygltf::FsCallbacks fs_callbacks(ResourceAccess& access) {
  return tinygltf::FsCallbacks{&allowed, &expand, &read_whole, &write_whole, &access};
}

}  // namespace aovar::scene::detail
