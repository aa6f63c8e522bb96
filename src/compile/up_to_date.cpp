#include "compile/up_to_date.h"

#include <sys/stat.h>

#include <algorithm>
#include <sstream>

#include <fmt/format.h>

#include "shadergen/expand.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::compile {
namespace fs = std::filesystem;

namespace {
constexpr const char* kStateFile = ".aovar-state";
constexpr const char* kFormat = "aovar-state 2";

// "size@seconds.nanoseconds" of the last write, or "missing". One stat() a file: a no-op checks thousands.
std::string file_signature(const fs::path& p) {
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return "missing";
  return std::to_string(st.st_size) + "@" + std::to_string(st.st_mtim.tv_sec) + "." + std::to_string(st.st_mtim.tv_nsec);
}

// The hash of what `path` holds now, "missing" when it cannot be read (as TemplateReader sees it), and
// "unreadable" when the checked reader refuses it (a directory, a device): never current, so the full run
// reads it again and reports it.
std::string content_hash(const fs::path& path) {
  try {
    auto text = util::read_file(path);
    return text ? util::hash_hex(*text) : "missing";
  } catch (const std::runtime_error&) {
    return "unreadable";
  }
}

// "<tag> <field> <rest of line>" (or "<tag> <rest>" without a field); the rest is a path and may hold spaces.
bool split(const std::string& line, std::string& tag, std::string& field, std::string& rest, bool with_field) {
  std::size_t a = line.find(' ');
  if (a == std::string::npos) return false;
  tag = line.substr(0, a);
  if (!with_field) return rest = line.substr(a + 1), true;
  std::size_t b = line.find(' ', a + 1);
  if (b == std::string::npos) return false;
  field = line.substr(a + 1, b - a - 1);
  rest = line.substr(b + 1);
  return true;
}
}  // namespace

std::string tool_identity() {
  return file_signature("/proc/self/exe") + " " + shadergen::generator_version() + " " + compiler_version();
}

std::string run_settings(const std::string& tool, const CompileOptions& co,
                         const OutputOptions& o) {
  util::Hasher h;
  h.add(tool).add(fs::absolute(co.scope.manifest.path()).lexically_normal().string());
  h.add("targets");
  for (auto t : co.scope.targets) h.add(variants::target_name(t));
  h.add("globs");
  for (const auto& g : co.globs) h.add(g);
  h.add("exclude");
  for (const auto& k : co.exclude) h.add(k);
  h.add(co.werror ? 1 : 0).add(o.emit).add(o.cpp_namespace);
  h.add("pick fronts");
  for (const auto& f : o.pick_fronts) {
    h.add(f.target).add(f.family ? 1 : 0);
    for (const auto& p : f.points) h.add(p.variant).add(fmt::format("{:.17g} {:.17g}", p.time_ms, p.rmse));
  }
  h.add("parameters");
  for (const auto& [owner, values] : o.parameters) {
    h.add(owner);
    for (const auto& [key, value] : values) h.add(key).add(fmt::format("{:.17g}", value));
  }
  return h.hex();
}

std::optional<RecordedRun> recorded_if_current(const std::string& settings, const OutputOptions& o) {
  auto state = util::read_file(o.out / kStateFile);
  if (!state) return std::nullopt;
  std::istringstream in(*state);
  std::string line, tag, field, rest;
  if (!std::getline(in, line) || line != kFormat) return std::nullopt;
  if (!std::getline(in, line) || line != "settings " + settings) return std::nullopt;
  RecordedRun run;
  while (std::getline(in, line)) {
    if (line == "summary") {
      std::string summary((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      run.summary = std::move(summary);
      return run.manifest.empty() ? std::nullopt : std::optional(std::move(run));
    }
    bool with_field = line.rfind("missing ", 0) != 0;
    if (!split(line, tag, field, rest, with_field)) return std::nullopt;
    if (tag == "manifest" || tag == "input") {
      if (content_hash(rest) != field) return std::nullopt;
      (tag == "manifest" ? run.manifest : run.files.emplace_back()) = rest;
    } else if (tag == "missing") {
      if (content_hash(rest) != "missing") return std::nullopt;
    } else if (tag == "output") {
      if (file_signature(o.out / rest) != field) return std::nullopt;
    } else {
      return std::nullopt;
    }
  }
  return std::nullopt;  // no summary: an incomplete state
}

void record_run(const std::string& settings, const CompiledSpace& c, const OutputOptions& o,
                const std::string& summary, const std::vector<fs::path>& outputs) {
  std::string state = std::string(kFormat) + "\nsettings " + settings + "\n";
  fs::path manifest = fs::absolute(c.manifest.path).lexically_normal();
  state += "manifest " + c.manifest.hash + " " + manifest.string() + "\n";
  for (std::size_t i = 0; i < c.files.size(); ++i) state += "input " + c.file_hashes[i] + " " + c.files[i].string() + "\n";
  for (const auto& p : c.files_missing) state += "missing " + p.string() + "\n";
  for (const auto& f : outputs) state += "output " + file_signature(f) + " " + f.lexically_relative(o.out).string() + "\n";
  state += "summary\n" + summary;
  // A path with a line break would not read back as written: record nothing (every run then builds).
  auto lines = std::count(state.begin(), state.end(), '\n') - std::count(summary.begin(), summary.end(), '\n');
  std::size_t expected = 4 + c.files.size() + c.files_missing.size() + outputs.size();
  if (static_cast<std::size_t>(lines) != expected) {
    std::error_code ec;
    fs::remove(o.out / kStateFile, ec);
    return;
  }
  util::write_if_changed(o.out / kStateFile, state);
}

}  // namespace aovar::compile
