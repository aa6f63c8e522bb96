#pragma once
// Expands one template into the complete source of one target: #version, target/stage/axis defines,
// then the template with every #include replaced in place. `#line <n> <k>` directives keep glslang's
// line numbers on the template files, with source-string number k naming the file (0 = the preamble).
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "variants/space.h"

namespace aovar::shadergen {

// Reads template files once and remembers every file read (for the depfile). Thread-safe: programs are
// expanded on the compile pool; a returned text stays valid as long as the reader.
class TemplateReader {
 public:
  explicit TemplateReader(const std::filesystem::path& root) : root_(std::filesystem::absolute(root).lexically_normal()) {}
  const std::filesystem::path& root() const { return root_; }
  // Contents of `path` (absolute or relative to root), or nullptr when missing.
  const std::string* read(const std::filesystem::path& path);
  std::vector<std::filesystem::path> files_read() const;
  // Paths looked up and not found (an include tried beside its includer first): a file appearing at one
  // changes the expansion, so a no-op check must see them still missing.
  std::vector<std::filesystem::path> files_missing() const;

 private:
  std::filesystem::path root_;
  mutable std::mutex mutex_;
  std::map<std::filesystem::path, std::unique_ptr<std::string>> files_;
};

struct ExpandedSource {
  std::string text;
  std::vector<std::filesystem::path> files;  // files[k - 1] is source-string k
};

// "file:line: error: what" for a template problem (missing include, missing template).
class TemplateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

ExpandedSource expand(TemplateReader& reader, const variants::ProgramSpec& program, variants::Target target,
                      const std::string& manifest_display);

// Text of the first line(s) the generator adds; the version is part of every program hash.
std::string generator_version();

}  // namespace aovar::shadergen
