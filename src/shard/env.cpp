// --shard auto: each scheduler's variables -> one 0-based shard index and count.
#include "shard/env.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace aovar::shard {
namespace {

const char* const kNames[] = {"AOVAR_SHARD_INDEX", "AOVAR_SHARD_TOTAL", "CI_NODE_INDEX", "CI_NODE_TOTAL",
                              "SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN",
                              "SLURM_ARRAY_TASK_STEP", "JOB_COMPLETION_INDEX", "TEST_SHARD_INDEX",
                              "TEST_TOTAL_SHARDS", "TEST_SHARD_STATUS_FILE"};

std::optional<std::string> get(const Env& env, const std::string& name) {
  auto it = env.find(name);
  if (it == env.end() || it->second.empty()) return std::nullopt;
  return it->second;
}

long number(const Env& env, const std::string& name) {
  const std::string& text = env.at(name);
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(text.c_str(), &end, 10);
  if (errno != 0 || end == text.c_str() || *end != '\0')
    throw std::runtime_error(fmt::format("--shard auto: {}='{}' is not an integer", name, text));
  return v;
}

// One convention: its index variable, its count variable, and how the index is read.
struct Convention {
  const char* name;
  const char* index_var;
  const char* count_var;
  bool one_based = false;
  bool slurm = false;
};

const Convention kConventions[] = {
    {"aovar", "AOVAR_SHARD_INDEX", "AOVAR_SHARD_TOTAL"},
    {"GitLab CI", "CI_NODE_INDEX", "CI_NODE_TOTAL", true},
    {"Slurm array", "SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", false, true},
    {"Kubernetes Indexed Job", "JOB_COMPLETION_INDEX", "AOVAR_SHARD_TOTAL"},
    {"Bazel", "TEST_SHARD_INDEX", "TEST_TOTAL_SHARDS"},
};

std::optional<ShardSpec> read_convention(const Convention& c, const Env& env) {
  if (!get(env, c.index_var)) return std::nullopt;
  std::vector<std::string> vars = {c.index_var, c.count_var};
  if (c.slurm) vars.push_back("SLURM_ARRAY_TASK_MIN");
  for (const auto& v : vars)
    if (!get(env, v))
      throw std::runtime_error(fmt::format("--shard auto: {} is set but {} is not ({}: set both, or pass --shard k/n)",
                                           c.index_var, v, c.name));
  long index = number(env, c.index_var), count = number(env, c.count_var);
  if (c.one_based) --index;
  if (c.slurm) {
    long step = get(env, "SLURM_ARRAY_TASK_STEP") ? number(env, "SLURM_ARRAY_TASK_STEP") : 1;
    if (get(env, "SLURM_ARRAY_TASK_STEP")) vars.push_back("SLURM_ARRAY_TASK_STEP");
    long offset = index - number(env, "SLURM_ARRAY_TASK_MIN");
    if (step < 1 || offset % step != 0)
      throw std::runtime_error(fmt::format("--shard auto: SLURM_ARRAY_TASK_ID={} is not on the array's range "
                                           "(MIN={}, STEP={}): use --array=0-N or pass --shard k/n",
                                           env.at("SLURM_ARRAY_TASK_ID"), env.at("SLURM_ARRAY_TASK_MIN"), step));
    index = offset / step;
  }
  if (count < 1 || index < 0 || index >= count)
    throw std::runtime_error(fmt::format("--shard auto: {}={} and {}={} give shard {} of {}, outside 1..{} ({})",
                                         c.index_var, env.at(c.index_var), c.count_var, env.at(c.count_var),
                                         index + 1, count, count, c.name));
  if (count > kMaxShards)
    throw std::runtime_error(fmt::format("--shard auto: {}={} asks for more than {} shards ({}): use fewer shards",
                                         c.count_var, env.at(c.count_var), kMaxShards, c.name));
  ShardSpec s;
  s.index = static_cast<int>(index);
  s.count = static_cast<int>(count);
  s.convention = c.name;
  for (const auto& v : vars) s.variables += (s.variables.empty() ? "" : " ") + v + "=" + env.at(v);
  return s;
}

}  // namespace

std::string ShardSpec::label() const { return fmt::format("{}/{}", index + 1, count); }

std::string ShardSpec::describe() const {
  return fmt::format("shard {} from {}{}", label(), convention, variables.empty() ? "" : " (" + variables + ")");
}

ShardSpec shard_from_env(const Env& env) {
  std::optional<ShardSpec> chosen;
  for (const auto& c : kConventions) {
    auto s = read_convention(c, env);
    if (!s) continue;
    if (!chosen) {
      chosen = s;
    } else if (s->index != chosen->index || s->count != chosen->count) {
      throw std::runtime_error(fmt::format("--shard auto: {} says shard {} but {} says {} ({} / {}): unset one, or "
                                           "pass --shard k/n",
                                           chosen->convention, chosen->label(), s->convention, s->label(),
                                           chosen->variables, s->variables));
    }
  }
  if (!chosen)
    throw std::runtime_error("--shard auto: no shard in the environment (AOVAR_SHARD_INDEX/AOVAR_SHARD_TOTAL, "
                             "CI_NODE_INDEX/CI_NODE_TOTAL, SLURM_ARRAY_TASK_ID/COUNT/MIN, JOB_COMPLETION_INDEX with "
                             "AOVAR_SHARD_TOTAL, TEST_SHARD_INDEX/TEST_TOTAL_SHARDS): set one or pass --shard k/n");
  if (get(env, "TEST_SHARD_INDEX"))  // Bazel set it (and agrees): its runner expects the file touched
    if (auto f = get(env, "TEST_SHARD_STATUS_FILE")) chosen->status_file = *f;
  return *chosen;
}

ShardSpec parse_shard_option(const std::string& text, const Env& env) {
  if (text.empty()) return {};
  if (text == "auto") return shard_from_env(env);
  // from_chars, not sscanf's %d: a count past INT_MAX must be refused, not wrapped.
  long long k = 0, n = 0;
  const std::size_t slash = text.find('/');
  auto whole = [&](std::size_t from, std::size_t to, long long& v) {
    auto [end, ec] = std::from_chars(text.data() + from, text.data() + to, v);
    return from < to && ec == std::errc() && end == text.data() + to;
  };
  if (slash == std::string::npos || !whole(0, slash, k) || !whole(slash + 1, text.size(), n) || n < 1 || k < 1 || k > n)
    throw std::runtime_error("--shard: expected k/n with 1 <= k <= n (e.g. 2/4) or auto, got '" + text + "'");
  if (n > kMaxShards)
    throw std::runtime_error(fmt::format("--shard {}: more than {} shards; use fewer shards", text, kMaxShards));
  ShardSpec s;
  s.index = static_cast<int>(k - 1);
  s.count = static_cast<int>(n);
  s.convention = "--shard";
  return s;
}

Env process_env() {
  Env env;
  for (const char* name : kNames)
    if (const char* v = std::getenv(name)) env[name] = v;
  return env;
}

void touch_status_file(const ShardSpec& spec) {
  if (spec.status_file.empty()) return;
  std::ofstream f(spec.status_file, std::ios::app);
  if (!f) throw std::runtime_error("--shard auto: cannot touch TEST_SHARD_STATUS_FILE " + spec.status_file);
}

}  // namespace aovar::shard
