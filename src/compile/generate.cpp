#include "compile/generate.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <fmt/format.h>
#include <map>
#include <set>
#include <sstream>
#include <exception>

#include "compile/cache.h"
#include "shadergen/expand.h"
#include "util/clock.h"
#include "util/fs.h"
#include "util/hash.h"
#include "util/parallel.h"
#include "util/path_names.h"

namespace aovar::compile {
namespace fs = std::filesystem;
using variants::Target;

int CompiledSpace::target_index(Target t) const {
  auto it = std::find(targets.begin(), targets.end(), t);
  return it == targets.end() ? -1 : static_cast<int>(it - targets.begin());
}

std::vector<std::string> CompiledSpace::variants_using(int program) const {
  std::vector<std::string> out;
  for (const auto& v : space.variants)
    for (const auto& pass : v.passes)
      if (pass[0] == program || pass[1] == program) {
        out.push_back(v.key);
        break;
      }
  return out;
}

std::string counts_line(const CompiledSpace& c) {
  if (c.space.filtered_out)  // --variants: dedup is over the selected variants only
    return fmt::format("space {} / rules {} / selected {} / dedup {}", c.space.space, c.space.collapsed,
                       c.space.variants.size(), c.dedup);
  return fmt::format("space {} / rules {} / dedup {}", c.space.space, c.space.collapsed, c.dedup);
}

namespace {

std::string program_hash(const std::string& text, variants::StageKind stage, Target target) {
  util::Hasher h;
  h.add(shadergen::generator_version()).add(compiler_version()).add(variants::target_name(target));
  h.add(variants::stage_name(stage)).add(text);
  return h.hex();
}

struct GroupedDiagnostic {  // one message at one place on one target, and how many programs share it
  std::string line;
  std::string first_program;
  std::string target;
  int others = 0;
};

}  // namespace

CompiledSpace plan_space(const CompileOptions& options) {
  auto start = std::chrono::steady_clock::now();
  CompiledSpace c;
  c.manifest = options.scope.manifest.get();
  c.space = variants::build_space(c.manifest, options.globs, options.exclude);
  c.targets = options.scope.targets.empty() ? c.manifest.targets : options.scope.targets;
  const auto& programs = c.space.programs;
  const std::string manifest_display = c.manifest.error_prefix();

  // Expand and hash every program for every target on the pool. A template error names the first failing
  // program in (target, program) order, as a serial run would, whichever thread met it first.
  shadergen::TemplateReader reader(c.manifest.root);
  const std::size_t count = c.targets.size() * programs.size();
  std::vector<shadergen::ExpandedSource> expanded(count);
  std::vector<std::exception_ptr> failed(count);
  c.builds.assign(c.targets.size(), std::vector<ProgramBuild>(programs.size()));
  util::run_parallel(count, options.scope.jobs, [&](std::size_t i) {
    std::size_t t = i / programs.size(), p = i % programs.size();
    try {
      expanded[i] = shadergen::expand(reader, programs[p], c.targets[t], manifest_display);
      c.builds[t][p].hash = program_hash(expanded[i].text, programs[p].stage, c.targets[t]);
    } catch (...) {
      failed[i] = std::current_exception();
    }
  });
  for (const auto& e : failed)
    if (e) std::rethrow_exception(e);
  c.files = reader.files_read();
  for (const auto& f : c.files) c.file_hashes.push_back(util::hash_hex(*reader.read(f)));
  c.files_missing = reader.files_missing();
  std::map<fs::path, int> file_index;
  for (std::size_t i = 0; i < c.files.size(); ++i) file_index[c.files[i]] = static_cast<int>(i);
  for (std::size_t i = 0; i < count; ++i) {
    ProgramBuild& b = c.builds[i / programs.size()][i % programs.size()];
    b.source = std::move(expanded[i].text);
    for (const auto& f : expanded[i].files) b.files.push_back(file_index.at(f));
  }

  c.seconds_compile = util::seconds_since(start);
  return c;
}

// Each program from the cache, or compiled (and stored) where the cache has no entry spirv-val accepts.
static void compile_or_reuse_programs(CompiledSpace& c, const CompileOptions& options) {
  const auto& programs = c.space.programs;
  CompileCache cache(options.scope.cache_dir);
  ValidationMemo validated;
  util::run_parallel(c.targets.size() * programs.size(), options.scope.jobs, [&](std::size_t i) {
    std::size_t t = i / programs.size(), p = i % programs.size();
    ProgramBuild& b = c.builds[t][p];
    auto hit = cache.load(b.hash);
    // Validated before use, as a fresh compile is: a cache never hands a driver SPIR-V spirv-val rejects.
    if (hit)
      if (const std::string errors = spirv_errors(hit->spirv, c.targets[t], &validated); !errors.empty()) {
        cache.reject(b.hash, errors);
        hit.reset();
      }
    if (hit) {
      b.output = std::move(*hit);
    } else {
      b.output = compile_program(b.source, programs[p].stage, c.targets[t], &validated);
      b.compiled = true;
      cache.store(b.hash, b.output);
    }
    b.ok = b.output.ok;
  });
}

void build_programs(CompiledSpace& c, const CompileOptions& options) {
  auto start = std::chrono::steady_clock::now();
  const auto& programs = c.space.programs;
  const std::string manifest_display = c.manifest.error_prefix();
  compile_or_reuse_programs(c, options);

  // Diagnostics, grouped so one template error shared by 400 programs reads as one line.
  std::map<std::string, GroupedDiagnostic> grouped;
  std::vector<std::string> order;
  auto report = [&](const std::string& line, const std::string& program, Target target) {
    std::string tn(variants::target_name(target));
    auto [it, fresh] = grouped.try_emplace(line + "\x1f" + tn, GroupedDiagnostic{line, program, tn});
    if (fresh) order.push_back(it->first);
    else ++it->second.others;
  };
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    for (std::size_t p = 0; p < programs.size(); ++p) {
      ProgramBuild& b = c.builds[t][p];
      for (const auto& d : b.output.diagnostics) {
        bool warning = d.severity == Diagnostic::Severity::warning;
        if (warning && options.werror) b.ok = false;
        std::string where;
        if (d.source > 0 && d.source <= static_cast<int>(b.files.size()))
          where = fmt::format("{}:{}: ", util::display_path(c.files[b.files[d.source - 1]]), d.line);
        else if (d.source == 0)
          where = fmt::format("{}: (generated preamble, line {}): ", programs[p].template_path, d.line);
        else
          where = util::display_path(c.manifest.root / programs[p].template_path) + ": ";
        std::string sev = !warning ? "error" : options.werror ? "error (warning, --werror)" : "warning";
        report(where + sev + ": " + d.message, programs[p].key, c.targets[t]);
      }
      if (b.ok) {  // every manifest parameter must be a float member of the stage's AOParams block
        for (const auto& param : programs[p].params) {
          auto it = std::find_if(b.output.params_block.begin(), b.output.params_block.end(),
                                 [&](const UniformMember& m) { return m.name == param.name; });
          if (it != b.output.params_block.end() && it->is_float) continue;
          b.ok = false;
          report(fmt::format("{}:{}:{}: error: parameter '{}' is not a float member of block AOParams in {}",
                             manifest_display, param.pos.line, param.pos.column, param.name,
                             programs[p].template_path),
                 programs[p].key, c.targets[t]);
        }
      }
    }
  }
  for (const auto& id : order) {
    const auto& g = grouped[id];
    bool is_error = g.line.find(": error") != std::string::npos;
    (is_error ? c.errors : c.warnings)++;
    std::string text = fmt::format("{} [{}; {}]", g.line, g.first_program, g.target);
    if (g.others) text += fmt::format(" (and {} more program{})", g.others, g.others == 1 ? "" : "s");
    c.diagnostics.push_back(std::move(text));
  }

  // Dedup: programs with identical SPIR-V (or identical preprocessed ES source) share one entry.
  c.stats.assign(c.targets.size(), TargetStats{});
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    std::map<std::string, int> first;
    TargetStats& s = c.stats[t];
    for (std::size_t p = 0; p < programs.size(); ++p) {
      ProgramBuild& b = c.builds[t][p];
      ++s.programs;
      (b.compiled ? s.compiled : s.cached)++;
      if (!b.ok) {
        ++s.failed;
        if (c.errors == 0) c.errors = 1;  // a failed program is an error even without a message
        continue;
      }
      auto [it, fresh] = first.emplace(b.output.identity, static_cast<int>(p));
      if (!fresh) {
        b.same_as = it->second;
        continue;
      }
      ++s.unique;
      s.spirv_bytes += b.output.spirv.size() * 4;
    }
  }

  // Variant dedup: same canonical programs on every target and same pipeline axes = same variant.
  std::map<std::string, int> seen;
  std::vector<variants::Axis> pipeline = c.manifest.pipeline_reads;
  for (const auto& pass : c.manifest.passes)
    for (auto a : pass.when.axes()) pipeline.push_back(a);
  // GLSL ES has no SPIR-V: its identity is the preprocessed text, which keeps dead functions. So when a
  // SPIR-V target was generated, variants are compared on the SPIR-V targets only.
  bool have_spirv = std::any_of(c.targets.begin(), c.targets.end(), [](Target t) { return t != Target::gles30; });
  c.variant_same_as.assign(c.space.variants.size(), -1);
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto& var = c.space.variants[v];
    std::string id;
    for (std::size_t t = 0; t < c.targets.size(); ++t)
      for (const auto& pass : var.passes)
        if (!(have_spirv && c.targets[t] == Target::gles30))
        for (int prog : pass) {
          int canon = prog < 0 ? prog : (c.builds[t][prog].same_as >= 0 ? c.builds[t][prog].same_as : prog);
          id += std::to_string(canon) + ",";
        }
    for (auto a : pipeline) id += std::to_string(var.point[variants::index(a)]) + ";";
    auto [it, fresh] = seen.emplace(id, static_cast<int>(v));
    if (!fresh) c.variant_same_as[v] = it->second;
  }
  c.dedup = seen.size();
  c.seconds_compile += util::seconds_since(start);
}

CompiledSpace compile_space(const CompileOptions& options) {
  CompiledSpace c = plan_space(options);
  build_programs(c, options);
  return c;
}

namespace {
// The namespace is both a C++ namespace and the embedding's file names (NS.h, NS.cpp): a plain identifier,
// not a keyword, not one the standard reserves (a leading underscore and capital, or two underscores).
void check_cpp_namespace(const std::string& ns) {
  static const std::set<std::string> keywords = {
      "alignas", "alignof", "and", "asm", "auto", "bool", "break", "case", "catch", "char", "class", "concept",
      "const", "consteval", "constexpr", "constinit", "continue", "co_await", "co_return", "co_yield",
      "decltype", "default", "delete", "do", "double", "else", "enum", "explicit", "export", "extern", "false",
      "float", "for", "friend", "goto", "if", "inline", "int", "long", "mutable", "namespace", "new",
      "noexcept", "not", "nullptr", "operator", "or", "private", "protected", "public", "register", "requires",
      "return", "short", "signed", "sizeof", "static", "struct", "switch", "template", "this", "throw",
      "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual", "void",
      "volatile", "while", "xor", "std"};
  auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  std::string why;
  if (ns.empty() || ns.size() > 200) why = "must be 1-200 characters";
  else if (std::isdigit(static_cast<unsigned char>(ns[0]))) why = "starts with a digit";
  else if (!std::all_of(ns.begin(), ns.end(), word)) why = "may hold only letters, digits and '_'";
  else if (keywords.count(ns)) why = "is a C++ keyword (or std)";
  else if (ns.find("__") != std::string::npos || (ns[0] == '_' && std::isupper(static_cast<unsigned char>(ns[1]))))
    why = "is reserved by the C++ standard (no '__', no '_' then a capital)";
  if (!why.empty())
    throw std::runtime_error(fmt::format("--namespace '{}': the C++ namespace and file name of the embedding {} "
                                         "(e.g. my_ssao)", util::printable_name(ns), why));
}
}  // namespace

OutputReport write_outputs(const CompiledSpace& c, const OutputOptions& o, int jobs) {
  if (!o.check) {  // what a killed earlier run was writing, in the folders generate writes (not the user's tree)
    util::remove_stale_temps(o.out, false);
    for (variants::Target t : c.targets) util::remove_stale_temps(o.out / std::string(variants::target_name(t)), false);
  }
  std::map<fs::path, std::string> files;
  if (o.emit & emit_index) files[o.out / "variants.json"] = index_json(c, o.parameters);
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    fs::path dir = o.out / std::string(variants::target_name(c.targets[t]));
    for (std::size_t p = 0; p < c.space.programs.size(); ++p) {
      const ProgramBuild& b = c.builds[t][p];
      if (!b.ok || b.same_as >= 0) continue;
      const std::string& key = c.space.programs[p].key;
      util::check_path_component(key, "program key");
      if (o.emit & emit_source) files[dir / key] = b.source;
      if ((o.emit & emit_spirv) && !b.output.spirv.empty())
        files[dir / (key + ".spv")] =
            std::string(reinterpret_cast<const char*>(b.output.spirv.data()), b.output.spirv.size() * 4);
    }
  }
  if (o.emit & emit_cpp) {
    check_cpp_namespace(o.cpp_namespace);
    auto [header, source] = cpp_embedding(c, o.cpp_namespace, o.pick_fronts, o.parameters);
    files[o.out / (o.cpp_namespace + ".h")] = std::move(header);
    files[o.out / (o.cpp_namespace + ".cpp")] = std::move(source);
  }

  // Written (or, with check, compared) on the thread pool: thousands of small files, each a read of the old
  // one and an atomic write, are I/O and system time that one thread would serialise after the compile.
  std::vector<const std::pair<const fs::path, std::string>*> entries;
  for (const auto& entry : files) entries.push_back(&entry);
  if (!o.check) {  // the folders first, so the writers do not race to create them
    std::set<fs::path> folders;
    for (const auto* entry : entries) folders.insert(entry->first.parent_path());
    for (const auto& folder : folders) fs::create_directories(folder);
  }
  enum Outcome : char { unchanged, written, differs, missing };
  std::vector<Outcome> outcome(entries.size(), unchanged);
  util::run_parallel(entries.size(), jobs, [&](std::size_t i) {
    const auto& [path, content] = *entries[i];
    if (o.check) {
      auto old = util::read_file(path);
      outcome[i] = !old ? missing : *old == content ? unchanged : differs;
    } else if (util::write_if_changed(path, content, util::Durability::replaceable) == util::WriteResult::written) {
      outcome[i] = written;
    }
  });
  OutputReport r;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const fs::path& path = entries[i]->first;
    r.files.push_back(path);
    if (outcome[i] == unchanged) {
      ++r.unchanged;
    } else if (o.check) {
      r.changed.push_back(util::display_path(path) + (outcome[i] == missing ? " (missing)" : " (differs)"));
    } else {
      ++r.written;
      r.changed.push_back(util::display_path(path));
    }
  }
  // Programs that no longer exist leave no stale files behind in the folders this run owns.
  if (o.emit & (emit_source | emit_spirv)) {
    for (Target t : c.targets) {
      fs::path dir = o.out / std::string(variants::target_name(t));
      std::error_code ec;
      for (const auto& entry : fs::directory_iterator(dir, ec)) {
        std::string ext = entry.path().extension().string();
        if (ext != ".vert" && ext != ".frag" && ext != ".spv") continue;
        if (files.count(entry.path())) continue;
        r.changed.push_back(util::display_path(entry.path()) + " (stale)");
        ++r.removed;
        if (!o.check) fs::remove(entry.path(), ec);
      }
    }
  }
  if (o.check) return r;
  finish_outputs(c.manifest.path, c.files, o);
  return r;
}

void finish_outputs(const fs::path& manifest, const std::vector<fs::path>& files, const OutputOptions& o) {
  if (o.depfile) {  // gcc-style: <output>: <manifest> <templates and includes>
    auto escape = [](const fs::path& p) {
      std::string s, raw = fs::absolute(p).lexically_normal().string();
      for (char ch : raw) {
        if (ch == ' ' || ch == '#') s += '\\';
        if (ch == '$') s += '$';
        s += ch;
      }
      return s;
    };
    std::string dep = escape(o.depfile_target.value_or(o.out / "variants.json")) + ":";
    dep += " \\\n  " + escape(manifest);
    for (const auto& f : files) dep += " \\\n  " + escape(f);
    for (const auto& f : o.depends) dep += " \\\n  " + escape(f);
    dep += "\n";
    util::write_if_changed(*o.depfile, dep);
  }
  if (o.stamp) util::write_atomic(*o.stamp, "");
}

}  // namespace aovar::compile
