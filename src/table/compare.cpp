#include "table/compare.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "util/fs.h"

namespace aovar::table {

TableDiff diff_tables(const CostTable& a, const CostTable& b) {
  std::map<std::string, const CostRow*> ra, rb;
  for (const auto& r : a.rows) ra.emplace(r.key(), &r);
  for (const auto& r : b.rows) rb.emplace(r.key(), &r);
  TableDiff d;
  for (const auto& [k, r] : ra)
    if (!rb.count(k)) d.only_a.push_back(k);
  for (const auto& [k, r] : rb)
    if (!ra.count(k)) d.only_b.push_back(k);

  struct Spec {
    const char* name;
    bool higher_better, relative;
    double threshold;
    bool (*has)(const CostRow&);
    double (*get)(const CostRow&);
  };
  const Spec specs[] = {
      {"time_ms.min", false, true, 0.02, [](const CostRow& r) { return !r.predicted; },
       [](const CostRow& r) { return r.time_ms.min; }},
      {"error.rmse", false, false, 1e-4, [](const CostRow& r) { return r.error.has_value(); },
       [](const CostRow& r) { return r.error->rmse; }},
      {"error.ssim", true, false, 1e-4, [](const CostRow& r) { return r.error.has_value(); },
       [](const CostRow& r) { return r.error->ssim; }},
  };
  for (const auto& [k, r] : ra) d.common += rb.count(k) ? 1 : 0;
  for (const Spec& s : specs) {
    MetricDiff m;
    m.metric = s.name;
    m.higher_is_better = s.higher_better;
    std::vector<Delta> helped, hurt;
    double pct_sum = 0;
    int pct_n = 0;
    for (const auto& [k, x] : ra) {
      auto it = rb.find(k);
      if (it == rb.end() || !s.has(*x) || !s.has(*it->second)) continue;
      Delta dl{k, s.get(*x), s.get(*it->second), 0};
      double delta = dl.b - dl.a;
      dl.pct = dl.a != 0 ? 100.0 * delta / std::abs(dl.a) : delta == 0 ? 0.0 : std::copysign(INFINITY, delta);
      m.total_a += dl.a;
      m.total_b += dl.b;
      if (std::isfinite(dl.pct)) {
        pct_sum += dl.pct;
        ++pct_n;
      }
      bool changed = s.relative ? (dl.a == 0 ? delta != 0 : std::abs(delta) > s.threshold * std::abs(dl.a))
                                : std::abs(delta) > s.threshold;
      if (!changed) {
        ++m.unchanged;
        continue;
      }
      bool better = s.higher_better ? delta > 0 : delta < 0;
      (better ? helped : hurt).push_back(dl);
    }
    m.helped = static_cast<int>(helped.size());
    m.hurt = static_cast<int>(hurt.size());
    m.mean_pct = pct_n ? pct_sum / pct_n : 0;
    auto by_size = [](const Delta& x, const Delta& y) {
      double ax = std::abs(x.pct), ay = std::abs(y.pct);
      return ax != ay ? ax > ay : x.key < y.key;
    };
    std::sort(helped.begin(), helped.end(), by_size);
    std::sort(hurt.begin(), hurt.end(), by_size);
    if (helped.size() > 10) helped.resize(10);
    if (hurt.size() > 10) hurt.resize(10);
    m.top_helped = std::move(helped);
    m.top_hurt = std::move(hurt);
    d.metrics.push_back(std::move(m));
  }
  return d;
}

namespace {
std::string pct_text(double p) {
  if (std::isinf(p)) return p > 0 ? "+inf%" : "-inf%";
  return fmt::format("{:+.2f}%", p);
}
}  // namespace

std::string format_diff(const TableDiff& d, const std::string& name_a, const std::string& name_b) {
  std::string s = fmt::format("A: {}\nB: {}\nrows in both: {}, only in A: {}, only in B: {}\n", name_a, name_b,
                              d.common, d.only_a.size(), d.only_b.size());
  for (const auto& m : d.metrics) {
    int n = m.helped + m.hurt + m.unchanged;
    double total_pct = m.total_a != 0 ? 100.0 * (m.total_b - m.total_a) / std::abs(m.total_a) : 0;
    s += fmt::format("\n{} ({} is better; {} rows)\n", m.metric, m.higher_is_better ? "higher" : "lower", n);
    s += fmt::format("  helped: {}  hurt: {}  unchanged: {}\n", m.helped, m.hurt, m.unchanged);
    if (n) {
      s += fmt::format("  total: {:.6g} -> {:.6g} ({})\n", m.total_a, m.total_b, pct_text(total_pct));
      s += fmt::format("  mean: {:.6g} -> {:.6g}, mean change {}\n", m.total_a / n, m.total_b / n, pct_text(m.mean_pct));
    }
    for (const auto* list : {&m.top_helped, &m.top_hurt}) {
      if (list->empty()) continue;
      s += fmt::format("  {} (top {}):\n", list == &m.top_helped ? "helped" : "hurt", list->size());
      for (const auto& dl : *list) s += fmt::format("    {}: {:.6g} -> {:.6g} ({})\n", dl.key, dl.a, dl.b, pct_text(dl.pct));
    }
  }
  auto list_keys = [&](const char* title, const std::vector<std::string>& keys) {
    if (keys.empty()) return;
    s += fmt::format("\n{} ({}):\n", title, keys.size());
    for (const auto& k : keys) s += "  " + k + "\n";
  };
  list_keys("only in A", d.only_a);
  list_keys("only in B", d.only_b);
  return s;
}

CostTable merge_tables(const std::vector<std::filesystem::path>& inputs) {
  if (inputs.empty()) throw std::runtime_error("merge: no input tables");
  CostTable out;
  nlohmann::json first_meta;
  std::map<std::string, std::pair<nlohmann::json, std::string>> seen;  // key -> row json, file
  nlohmann::json from = nlohmann::json::array();
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    std::string name = util::display_path(inputs[i]);
    CostTable t = read_table(inputs[i]);
    nlohmann::json meta = t.meta;
    if (meta.is_object()) meta.erase("shard");
    if (meta.is_object()) meta.erase("reps_reached");  // what each shard's timing reached: its own
    if (i == 0) {
      first_meta = meta;
    } else if (meta != first_meta) {
      std::string field;
      for (const auto& [k, v] : first_meta.items())
        if (!meta.contains(k) || meta[k] != v) { field = k; break; }
      if (field.empty())
        for (const auto& [k, v] : meta.items())
          if (!first_meta.contains(k)) { field = k; break; }
      throw std::runtime_error(fmt::format("merge: {} and {} come from different runs (meta '{}' differs)",
                                           util::display_path(inputs[0]), name, field));
    }
    from.push_back(name);
    for (auto& r : t.rows) {
      r.pareto = false;  // recomputed over the merged table
      nlohmann::json j = to_json(r);
      auto [it, fresh] = seen.try_emplace(r.key(), j, name);
      if (!fresh) {
        if (it->second.first != j)
          throw std::runtime_error(fmt::format("merge: conflicting rows for {} in {} and {}", r.key(),
                                               it->second.second, name));
        continue;
      }
      out.rows.push_back(std::move(r));
    }
  }
  out.meta = first_meta.is_object() ? first_meta : nlohmann::json::object();
  out.meta["merged_from"] = from;
  mark_pareto(out);
  return out;
}

}  // namespace aovar::table
