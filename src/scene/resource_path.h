#pragma once
// The one path policy for the files a scene file names (a glTF's buffers and images): a scene names
// resources beside it or below it, nothing else. A hostile or careless .gltf must not make aovar read
// /etc/passwd as vertex positions, or anything outside the folder the user pointed it at.
#include <filesystem>
#include <string>
#include <string_view>

namespace aovar::scene {

// True for a "data:" URI (its bytes are inline in the scene file; no file is read).
bool is_data_uri(std::string_view uri);

// The file the relative URI reference `uri` (RFC 3986, as glTF 2.0 uses it; not a data: URI) names beside or
// below `scene_file`: percent-escapes and '+' decoded as tinygltf decodes them, then the result lexically
// normal under the scene's folder. Refused, with SceneError "<display>: error: <what> '<uri>': <why> (...)"
// naming the scene file and the URI: a scheme ("file:", "http:", "C:"), an absolute path, a ".." segment, a
// backslash, a control byte, an encoded '.', '/', '\', '%' or control byte (%2e, %2F, %5c, %25, %00), a
// malformed escape, and a path that a symbolic link takes outside the scene's folder. `what` says which
// reference it is ("buffer 0", "image 3").
std::filesystem::path resolve_resource(const std::filesystem::path& scene_file, const std::string& display,
                                       const std::string& what, std::string_view uri);

}  // namespace aovar::scene
