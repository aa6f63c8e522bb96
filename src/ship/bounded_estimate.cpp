#include "ship/bounded_estimate.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <iterator>
#include <stdexcept>
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
                        const std::function<void(const std::vector<BoundCandidate*>&, int)>& trace,
                        const std::function<void(const std::vector<BoundCandidate*>&)>& complete,
                        const std::function<void(const std::vector<BoundCandidate*>&, int)>& refine) {
  std::sort(candidates.begin(), candidates.end(), [](const BoundCandidate& a, const BoundCandidate& b) {
    return std::tie(a.error, a.bound, a.key) < std::tie(b.error, b.bound, b.key);
  });
  std::vector<const BoundCandidate*> traced;  // every stage traced: est is the worst view's estimate
  auto beater = [&](const BoundCandidate& c) -> const BoundCandidate* {
    if (c.key == keep) return nullptr;
    const BoundCandidate* by = nullptr;
    for (const BoundCandidate* d : traced)
      if (d->error < c.error && d->est < c.bound && (!by || d->est < by->est)) by = d;
    return by;
  };
  auto beaten = [&](BoundCandidate& c) {
    const BoundCandidate* by = beater(c);
    if (by) c.beaten_by = by->key;
    return by != nullptr;
  };
  std::size_t next = 0;  // the first candidate not yet visited
  std::vector<BoundCandidate*> pending;
  auto complete_pending = [&] {  // every view's error before the last stage: it may already decide
    std::vector<BoundCandidate*> incomplete;
    for (BoundCandidate* c : pending)
      if (!c->complete) incomplete.push_back(c);
    if (incomplete.empty()) return;
    complete(incomplete);
    std::erase_if(pending, [&](BoundCandidate* c) { return beaten(*c); });
  };
  auto flush = [&] {
    for (int stage = 0; stage < stages && !pending.empty(); ++stage) {
      if (complete && stage + 1 == stages) {
        complete_pending();
        if (pending.empty()) break;
      }
      if (refine) {
        refine(pending, stage);
        std::erase_if(pending, [&](BoundCandidate* c) { return beaten(*c); });
        if (pending.empty()) break;
      }
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
  while (next < candidates.size()) {
    BoundCandidate& c = candidates[next++];
    if (beaten(c)) continue;
    pending.push_back(&c);
    if (int(pending.size()) >= chunk) flush();
  }
  flush();
}

namespace {

// One family's candidates: each one's rows on the training views (in the screen or rendered since).
struct FamilyRows {
  std::map<std::string, std::vector<table::CostRow*>> rows;

  // Its worst error so far and its ALU bound (the same on every view: no trace).
  BoundCandidate candidate(const std::string& key, const std::string& family) const {
    BoundCandidate c;
    c.key = key;
    for (const table::CostRow* r : rows.at(key)) {
      c.error = std::max(c.error, r->error->rmse);
      c.bound = std::max(c.bound, alu_lower_bound_ms(r->gpu.at(family)));
    }
    return c;
  }
};

// A bound on a row's traced estimate: the traced estimate of each pass `cached` holds (pass -> ms), the ALU
// time of the others.
double bound_with_cached(const table::GpuCost& cost, const std::map<std::string, double>& cached) {
  double sum = 0;
  for (const auto& p : cost.passes)
    if (auto it = cached.find(p.pass); it != cached.end() && !std::isnan(it->second)) sum += it->second;
    else if (!std::isnan(p.alu_ms)) sum += p.alu_ms;
  return sum;
}

bool is_candidate_row(const table::CostRow& r, const std::vector<std::string>& training, const std::string& family) {
  return r.error && !r.predicted && r.gpu.count(family) &&
         std::find(training.begin(), training.end(), r.view) != training.end();
}

std::string elimination_reason(const BoundCandidate& c, const BoundCandidate& by, const std::string& family,
                               const std::vector<std::string>& training) {
  const std::string shared = "the traffic other candidates' traces simulated for the draws it shares and the ALU "
                             "time of the rest";
  const std::string bound = c.bound_traced && c.bound_cached
                                ? "its estimate on " + training.front() + ", and on its other views " + shared
                            : c.bound_traced ? "its estimate on " + training.front() + " alone"
                            : c.bound_cached ? shared + ", untraced"
                                             : std::string("the ALU time alone, untraced");
  const std::string error = c.complete ? fmt::format("with more error ({:.4f} > {:.4f})", c.error, by.error)
                                       : fmt::format("with more error on {} alone ({:.4f} > {:.4f}; its other views "
                                                     "not rendered)", training.front(), c.error, by.error);
  return fmt::format("its {} estimate cannot be below {:.4f} ms ({}), more than {}'s traced {:.4f} ms, {}", family,
                     c.bound, bound, by.key, by.est, error);
}

}  // namespace

BoundedEstimate estimate_in_error_order(table::CostTable& screen, const std::vector<std::string>& training,
                                        const trace::RowGpuRequest& request, const std::string& keep,
                                        const std::function<void(const std::string&)>& say, int chunk,
                                        const RenderRest& render_rest) {
  const std::string& family = request.gpu.families.at(0);
  BoundedEstimate out;
  std::vector<table::CostRow*> all;
  for (auto& r : screen.rows) all.push_back(&r);
  trace::RowGpuRequest statistics = request;
  statistics.gpu.trace = false;
  out.gpu = trace::add_gpu_costs(all, statistics, say);
  out.gpu.traced = true;
  out.gpu.window_share = request.gpu.window;
  // RADV's statistics depend on the variant's programs, not the view: the other views' rows take them from the
  // first view's, copied before any trace, rather than compile every chunk's pipelines again.
  std::map<std::string, table::GpuCosts> statistics_of;
  if (render_rest)
    for (const auto& r : screen.rows) statistics_of.emplace(r.variant, r.gpu);

  FamilyRows fc;
  for (auto& r : screen.rows)
    if (is_candidate_row(r, training, family)) fc.rows[r.variant].push_back(&r);
  std::vector<BoundCandidate> candidates;
  for (const auto& [key, rows] : fc.rows) {
    candidates.push_back(fc.candidate(key, family));
    candidates.back().complete = rows.size() == training.size();
    if (!candidates.back().complete && !render_rest)
      throw std::logic_error("estimate_in_error_order: " + key + " lacks a training view");
  }
  std::deque<table::CostRow> rendered;  // the other views' rows (a deque: fc holds pointers to them)
  auto complete = [&](const std::vector<BoundCandidate*>& chunk_of) {
    std::vector<std::string> keys;
    for (const BoundCandidate* c : chunk_of)
      if (!c->complete) keys.push_back(c->key);
    if (keys.empty()) return;
    std::vector<table::CostRow*> fresh, unknown;
    for (table::CostRow& r : render_rest(keys)) {
      table::CostRow* row = &rendered.emplace_back(std::move(r));
      fresh.push_back(row);
      if (auto it = statistics_of.find(row->variant); it != statistics_of.end()) row->gpu = it->second;
      else unknown.push_back(row);
    }
    if (!unknown.empty()) trace::add_gpu_costs(unknown, statistics, [](const std::string&) {});
    for (table::CostRow* r : fresh)
      if (is_candidate_row(*r, training, family)) fc.rows[r->variant].push_back(r);
    for (BoundCandidate* c : chunk_of) {
      if (c->complete) continue;
      if (fc.rows.at(c->key).size() != training.size())
        throw std::runtime_error("ship: the screen's other training views gave no still of " + c->key);
      c->error = fc.candidate(c->key, family).error;  // the worst of every view now
      c->complete = true;
      ++out.completed;
    }
  };
  // Stage 0 traces the first training view, stage 1 the others (each candidate's rows are in view order).
  const int stages = training.size() > 1 ? 2 : 1;
  auto rows_of_stage = [&](const std::vector<BoundCandidate*>& chunk_of, int stage) {
    std::vector<std::pair<BoundCandidate*, table::CostRow*>> rows;
    for (BoundCandidate* c : chunk_of)
      for (table::CostRow* r : fc.rows[c->key])
        if ((r->view == training.front()) == (stage == 0)) rows.emplace_back(c, r);
    return rows;
  };
  trace::RowTracer tracer(request);
  std::set<std::string> candidate_keys;
  for (const BoundCandidate& c : candidates) candidate_keys.insert(c.key);
  tracer.expect(candidate_keys);  // one compilation for every chunk
  // Most draws are shared (every blur variant of a method has its AO draw, one blur program serves many
  // methods), so a candidate's shared passes are often simulated before it is reached: their traced estimates
  // and the ALU time of its other passes bound its estimate before its own trace (trace::RowTracer::cached).
  auto refine = [&](const std::vector<BoundCandidate*>& chunk_of, int stage) {
    const auto rows = rows_of_stage(chunk_of, stage);
    std::vector<table::CostRow*> just_rows;
    for (const auto& [c, r] : rows) just_rows.push_back(r);
    const auto cached = tracer.cached(just_rows, family);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const double bound = bound_with_cached(rows[i].second->gpu.at(family), cached[i]);
      BoundCandidate& c = *rows[i].first;
      if (bound > c.bound) c.bound = bound, c.bound_cached = true;
    }
  };
  auto trace_stage = [&](const std::vector<BoundCandidate*>& chunk_of, int stage) {
    std::vector<table::CostRow*> traced_rows;
    for (const auto& [c, r] : rows_of_stage(chunk_of, stage)) traced_rows.push_back(r);
    out.gpu.traffic += tracer.trace(traced_rows);
    for (BoundCandidate* c : chunk_of)
      for (const table::CostRow* r : fc.rows[c->key])
        if (stage == 1 || r->view == training.front()) c->est = std::max(c->est, r->gpu.at(family).est_ms);
    out.traced += stage + 1 == stages ? int(chunk_of.size()) : 0;
    out.first_view_traced += stage == 0 ? int(chunk_of.size()) : 0;
    if (say && stage + 1 == stages)
      say(fmt::format("estimated {} of {} candidates in order of error", out.traced, candidates.size()));
  };
  std::function<void(const std::vector<BoundCandidate*>&)> completion;  // none: every candidate is complete
  if (render_rest) completion = complete;
  eliminate_by_bound(candidates, keep, chunk, stages, trace_stage, completion, refine);
  out.gpu.traffic += tracer.trace({});  // what the last refinements read from the cache dir

  std::map<std::string, const BoundCandidate*> index;
  for (const auto& c : candidates) index[c.key] = &c;
  for (const auto& c : candidates) {
    if (c.beaten_by.empty()) continue;
    out.dropped_early += c.complete ? 0 : 1;
    out.eliminated.push_back({c.key, fc.rows[c.key].front()->backend, c.beaten_by,
                              elimination_reason(c, *index.at(c.beaten_by), family, training)});
  }
  std::move(rendered.begin(), rendered.end(), std::back_inserter(screen.rows));
  std::erase_if(screen.rows, [&](const table::CostRow& r) {
    auto it = index.find(r.variant);
    return it != index.end() && !it->second->beaten_by.empty();
  });
  std::sort(out.eliminated.begin(), out.eliminated.end(),
            [](const Elimination& a, const Elimination& b) { return a.variant < b.variant; });
  return out;
}

}  // namespace aovar::ship
