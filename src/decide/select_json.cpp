// `aovar select --json`: the typed Selection the text is written from, as JSON (NaN and infinities: null).
#include "decide/select.h"
#include "util/schema.h"

#include <fmt/format.h>

#include <stdexcept>

namespace aovar::decide {

namespace {
using nlohmann::json;

json candidate_json(const Candidate& c) {
  return {{"variant", c.variant},
          {"backend", c.backend},
          {"time_ms", c.time_ms},
          {"time_ci", interval_json(c.time_ci)},
          {"rmse", c.rmse},
          {"ssim", c.ssim},
          {"views", c.views},
          {"worst_error_view", c.worst_error_view},
          {"worst_time_view", c.worst_time_view},
          {"work_per_pixel", c.work_per_pixel}};
}

json candidates_json(const std::vector<Candidate>& list) {
  json out = json::array();
  for (const auto& c : list) out.push_back(candidate_json(c));
  return out;
}

json optional_json(const std::optional<Candidate>& c) { return c ? candidate_json(*c) : json(nullptr); }

}  // namespace

json to_json(const SelectQuery& q) {
  return {{"budget_ms", q.budget_ms ? json(*q.budget_ms) : json(nullptr)},
          {"budget_of", q.budget_of},
          {"max_error", q.max_error ? json(*q.max_error) : json(nullptr)},
          {"tolerance", q.tolerance},
          {"scene", q.scene},
          {"view", q.view},
          {"backend", q.backend},
          {"target", q.target}};
}

SelectQuery query_from_json(const json& j) {
  if (!j.is_object()) throw std::runtime_error("select query: not a JSON object");
  const auto bad = [](const char* name, const char* what) {
    return std::runtime_error(fmt::format("select query: \"{}\" is not {}", name, what));
  };
  // An absent field or null: the query's default (no budget, no filter).
  const auto number = [&](const char* name) -> std::optional<double> {
    const auto it = j.find(name);
    if (it == j.end() || it->is_null()) return std::nullopt;
    if (!it->is_number()) throw bad(name, "a number");
    return it->get<double>();
  };
  const auto text = [&](const char* name) {
    const auto it = j.find(name);
    if (it == j.end() || it->is_null()) return std::string();
    if (!it->is_string()) throw bad(name, "a string");
    return it->get<std::string>();
  };
  SelectQuery q;
  q.budget_ms = number("budget_ms");
  q.budget_of = text("budget_of");
  q.max_error = number("max_error");
  q.tolerance = number("tolerance").value_or(q.tolerance);
  q.scene = text("scene");
  q.view = text("view");
  q.backend = text("backend");
  q.target = text("target");
  return q;
}

json to_json(const Selection& s) {
  json margin = nullptr;
  if (s.margin)
    margin = {{"ratio", s.margin->ratio},
              {"ci", interval_json(s.margin->ci)},
              {"verdict", verdict_name(s.margin->verdict)},
              {"method", s.margin->method}};
  return {{"schema_version", util::kSchemaVersion},
          {"tool", "aovar select"},
          {"query", to_json(s.query)},
          {"ok", s.ok},
          {"choice", optional_json(s.choice)},
          {"reason", s.reason},
          {"interval", interval_json(s.choice_ci)},
          {"may_exceed_budget", s.may_exceed_budget},
          {"tied", candidates_json(s.tied)},
          {"runners_up", candidates_json(s.runners_up)},
          {"margin", margin},
          {"consider", optional_json(s.consider)},
          {"nearest", optional_json(s.nearest)}};
}

}  // namespace aovar::decide
