#include "ship/bounded_estimate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>

namespace aovar::ship {

double alu_lower_bound_ms(const table::GpuCost& cost) {
  double sum = 0;
  for (const auto& p : cost.passes)
    if (!std::isnan(p.alu_ms)) sum += p.alu_ms;
  return sum;
}

void eliminate_by_bound(std::vector<BoundCandidate>& candidates, const std::string& keep, int chunk, int stages,
                        const std::function<void(const std::vector<BoundCandidate*>&, int)>& trace) {
  std::sort(candidates.begin(), candidates.end(), [](const BoundCandidate& a, const BoundCandidate& b) {
    return std::tie(a.error, a.bound, a.key) < std::tie(b.error, b.bound, b.key);
  });
  std::vector<const BoundCandidate*> traced;  // every stage traced: est is the worst view's estimate
  auto beaten = [&](BoundCandidate& c) {
    if (c.key == keep) return false;
    const BoundCandidate* by = nullptr;
    for (const BoundCandidate* d : traced)
      if (d->error < c.error && d->est < c.bound && (!by || d->est < by->est)) by = d;
    if (by) c.beaten_by = by->key;
    return by != nullptr;
  };
  std::vector<BoundCandidate*> pending;
  auto flush = [&] {
    for (int stage = 0; stage < stages && !pending.empty(); ++stage) {
      trace(pending, stage);
      if (stage + 1 == stages) break;
      for (BoundCandidate* c : pending)  // the worst view so far: a bound on the worst of all
        if (c->est > c->bound) c->bound = c->est, c->bound_traced = true;
      std::erase_if(pending, [&](BoundCandidate* c) { return beaten(*c); });
    }
    for (BoundCandidate* c : pending) {
      c->traced = true;
      traced.push_back(c);
    }
    pending.clear();
  };
  for (BoundCandidate& c : candidates) {
    if (beaten(c)) continue;
    pending.push_back(&c);
    if (int(pending.size()) >= chunk) flush();
  }
  flush();
}

BoundedEstimate estimate_in_error_order(table::CostTable& screen, const std::vector<std::string>& training,
                                        const trace::RowGpuRequest& request, const std::string& keep,
                                        const std::function<void(const std::string&)>& say, int chunk) {
  const std::string& family = request.gpu.families.at(0);
  BoundedEstimate out;
  std::vector<table::CostRow*> all;
  for (auto& r : screen.rows) all.push_back(&r);
  trace::RowGpuRequest statistics = request;
  statistics.gpu.trace = false;
  out.gpu = trace::add_gpu_costs(all, statistics, say);
  out.gpu.traced = true;
  out.gpu.window_share = request.gpu.window;

  // Each candidate's training rows, its worst error and its bound.
  std::map<std::string, std::vector<table::CostRow*>> rows;
  std::map<std::string, BoundCandidate> by_key;
  for (auto& r : screen.rows) {
    if (!r.error || r.predicted || !r.gpu.count(family)) continue;
    if (std::find(training.begin(), training.end(), r.view) == training.end()) continue;
    BoundCandidate& c = by_key[r.variant];
    c.key = r.variant;
    c.error = std::max(c.error, r.error->rmse);
    c.bound = std::max(c.bound, alu_lower_bound_ms(r.gpu.at(family)));
    rows[r.variant].push_back(&r);
  }
  std::vector<BoundCandidate> candidates;
  for (auto& [key, c] : by_key) candidates.push_back(std::move(c));
  // Stage 0 traces the first training view, stage 1 the others (each candidate's rows are in view order).
  const int stages = training.size() > 1 ? 2 : 1;
  eliminate_by_bound(candidates, keep, chunk, stages, [&](const std::vector<BoundCandidate*>& chunk_of, int stage) {
    std::vector<table::CostRow*> traced_rows;
    for (const BoundCandidate* c : chunk_of)
      for (table::CostRow* r : rows[c->key])
        if ((r->view == training.front()) == (stage == 0)) traced_rows.push_back(r);
    out.gpu.traffic += trace::add_row_traffic(traced_rows, request);
    for (BoundCandidate* c : chunk_of)
      for (const table::CostRow* r : rows[c->key])
        if (stage == 1 || r->view == training.front()) c->est = std::max(c->est, r->gpu.at(family).est_ms);
    out.traced += stage + 1 == stages ? int(chunk_of.size()) : 0;
    if (say && stage + 1 == stages)
      say(fmt::format("estimated {} of {} candidates in order of error", out.traced, candidates.size()));
  });

  std::map<std::string, const BoundCandidate*> index;
  for (const auto& c : candidates) index[c.key] = &c;
  for (const auto& c : candidates) {
    if (c.beaten_by.empty()) continue;
    const BoundCandidate& by = *index.at(c.beaten_by);
    out.eliminated.push_back({c.key, rows[c.key].front()->backend, by.key,
                              fmt::format("its {} estimate cannot be below {:.4f} ms ({}), more than {}'s traced "
                                          "{:.4f} ms, with more error ({:.4f} > {:.4f})",
                                          family, c.bound,
                                          c.bound_traced ? "its estimate on " + training.front() + " alone"
                                                         : std::string("the ALU time alone, untraced"),
                                          by.key, by.est, c.error, by.error)});
  }
  std::erase_if(screen.rows, [&](const table::CostRow& r) {
    auto it = index.find(r.variant);
    return it != index.end() && !it->second->beaten_by.empty();
  });
  std::sort(out.eliminated.begin(), out.eliminated.end(),
            [](const Elimination& a, const Elimination& b) { return a.variant < b.variant; });
  return out;
}

}  // namespace aovar::ship
