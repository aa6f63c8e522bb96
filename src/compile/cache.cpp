#include "compile/cache.h"

#include <cstdlib>
#include <cstring>

#include "util/fs.h"

namespace aovar::compile {
namespace fs = std::filesystem;

namespace {
constexpr std::string_view kMagic = "aovar-compile-cache 3\n";

void put_u32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }
void put_str(std::string& s, std::string_view v) {
  put_u32(s, static_cast<std::uint32_t>(v.size()));
  s.append(v);
}

struct Reader {
  std::string_view data;
  bool ok = true;
  std::uint32_t u32() {
    if (data.size() < 4) return ok = false, 0;
    std::uint32_t v;
    std::memcpy(&v, data.data(), 4);
    data.remove_prefix(4);
    return v;
  }
  std::string str() {
    std::uint32_t n = u32();
    if (!ok || data.size() < n) return ok = false, std::string();
    std::string v(data.substr(0, n));
    data.remove_prefix(n);
    return v;
  }
};
}  // namespace

fs::path CompileCache::default_dir() {
  if (const char* d = std::getenv("AOVAR_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return fs::path(d) / "aovar";
  if (const char* d = std::getenv("HOME"); d && *d) return fs::path(d) / ".cache" / "aovar";
  return fs::temp_directory_path() / "aovar-cache";
}

std::optional<CompileOutput> CompileCache::load(const std::string& hash) const {
  const std::optional<std::string> bytes = cache_.read(hash);
  if (!bytes || bytes->rfind(kMagic, 0) != 0) return std::nullopt;
  Reader r{std::string_view(*bytes).substr(kMagic.size())};
  CompileOutput out;
  out.ok = true;
  out.identity = r.str();
  for (std::uint32_t n = r.u32(), i = 0; r.ok && i < n; ++i) {
    Diagnostic d;
    d.severity = r.u32() ? Diagnostic::Severity::warning : Diagnostic::Severity::error;
    d.source = static_cast<int>(r.u32()) - 1;
    d.line = static_cast<int>(r.u32());
    d.message = r.str();
    out.diagnostics.push_back(std::move(d));
  }
  for (std::uint32_t n = r.u32(), i = 0; r.ok && i < n; ++i) {
    UniformMember m;
    m.is_float = r.u32() != 0;
    m.name = r.str();
    out.params_block.push_back(std::move(m));
  }
  std::string spirv = r.str();
  if (!r.ok || spirv.size() % 4) {  // checksummed, so written wrong by another build: recompile
    cache_.reject(hash, "a compile output that does not decode");
    return std::nullopt;
  }
  out.spirv.resize(spirv.size() / 4);
  if (!spirv.empty()) std::memcpy(out.spirv.data(), spirv.data(), spirv.size());  // no SPIR-V (gles30): data() may be null
  return out;
}

void CompileCache::store(const std::string& hash, const CompileOutput& out) const {
  if (!enabled() || !out.ok) return;
  std::string s(kMagic);
  put_str(s, out.identity);
  put_u32(s, static_cast<std::uint32_t>(out.diagnostics.size()));
  for (const auto& d : out.diagnostics) {
    put_u32(s, d.severity == Diagnostic::Severity::warning);
    put_u32(s, static_cast<std::uint32_t>(d.source + 1));
    put_u32(s, static_cast<std::uint32_t>(d.line));
    put_str(s, d.message);
  }
  put_u32(s, static_cast<std::uint32_t>(out.params_block.size()));
  for (const auto& m : out.params_block) {
    put_u32(s, m.is_float);
    put_str(s, m.name);
  }
  put_str(s, std::string_view(reinterpret_cast<const char*>(out.spirv.data()), out.spirv.size() * 4));
  cache_.write(hash, s);  // an unwritable cache warns once and only costs speed
}

}  // namespace aovar::compile
