#include "ship/ship.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calibrate/calibrate.h"
#include "decide/pareto.h"
#include "gpu/by_key.h"
#include "gpu/family_specs.h"
#include "profile/scene_prune.h"
#include "report/report.h"
#include "scene/scene.h"
#include "ship/bounded_estimate.h"
#include "ship/fit.h"
#include "ship/profiled_space.h"
#include "ship/reference_prefetch.h"
#include "ship/shards.h"
#include "table/on_views.h"
#include "sweep/sweep.h"
#include "util/clock.h"
#include "util/fs.h"
#include "util/glob.h"
#include "util/hash.h"
#include "util/parallel.h"
#include "util/shell.h"
#include "util/text.h"
#include "variants/manifest.h"
#include "variants/space.h"

namespace aovar::ship {
using json = nlohmann::json;

namespace {

void check_query(const decide::SelectQuery& q) {
  const int criteria = int(q.budget_ms.has_value()) + int(!q.budget_of.empty()) + int(q.max_error.has_value());
  if (criteria != 1) throw std::runtime_error("ship: give exactly one of --budget-of KEY, --budget-ms X, --max-error E");
}

// The rounds: a screen of every candidate (the still error only: no flicker along the camera path, no images),
// then the survivors with every measure of a sweep. The measured backend times the screen with a few
// repetitions and the survivors with --reps auto; with a GPU target the time is the estimate: the screen renders
// only the frames each still needs (no timed frame) and the front one timed frame, for its report.
const char* round_name(bool target, bool final_round) { return !final_round ? "screen" : target ? "front" : "race"; }

int batch_of(const ShipOptions& o) { return o.batch > 0 ? o.batch : batch_for(o.size); }

bool estimated(const ShipOptions& o) { return !o.targets.empty(); }

// Where an elimination happened: the round, and with several targets the one it was eliminated on.
std::string round_on(const std::string& round, const ShipOptions& o, const std::string& target) {
  return o.targets.size() > 1 ? round + " on " + target : round;
}

// The race stops timing a candidate once another (of its batch, or of an earlier one) is faster beyond the
// noise and more accurate (measure::Retire): no margin, since that decides only how long it is timed, not whether it stays. Under
// --budget-of (the held-out views) the same holds for the budget's variant: select's test of a fit is "not
// slower beyond the noise".
constexpr double kRetireMargin = 1.0;

// One round: a sweep of `globs` (minus `skip`) on every view into OUT/<name>, resumable.
sweep::SweepOptions round_options(const ShipOptions& o, const Fitted& fit, const std::vector<std::string>& views,
                                  const std::vector<std::string>& globs, const std::set<std::string>& skip,
                                  bool final_round) {
  sweep::SweepOptions s;
  s.scenes = {o.scene};
  s.out = o.out / round_name(estimated(o), final_round);
  measure::MeasureOptions& m = s.measure;
  m.scope = o.scope;
  m.views_file = o.views_file;
  m.views = views;
  m.backends = {o.backend};
  m.globs = globs;
  m.skip = skip;
  m.size = o.size;
  m.timing.batch = batch_of(o);
  // The stills render on a device per worker thread (TimingPlan::still_devices), at most 4: measured on 2 cores
  // only, and each device keeps its own pipelines, G-buffers and scene.
  m.timing.still_devices = static_cast<int>(std::min(4u, util::pool_threads(o.scope.jobs)));
  m.truth.rays = o.rays;
  m.calibration = fit.calibration;
  // The budget's variant is timed in every round: each candidate is compared with it in the same rounds.
  if (!o.query.budget_of.empty()) m.baseline = o.query.budget_of;
  s.prune_by_profile = false;  // ship pruned already (the skip list), with the profile of all views
  m.images = m.truth.temporal = final_round;
  if (estimated(o)) {  // the time is the estimate: one render for the error
    m.timing.reps = 1;
    m.timing.warmup = 0;
    m.timing.still_only = !final_round;  // the front's rows keep one timed frame: its report draws time against error
    // The screen renders only: its candidates are estimated afterwards, in order of error (bounded_estimate.h).
    if (final_round) s.gpu.families = o.targets;
    s.gpu.frame = o.gpu_frame;
    s.gpu.window = o.gpu_window;
  } else if (final_round) {
    m.timing.reps = o.race_reps;
    m.timing.auto_reps = o.final_reps;
  } else {
    m.timing.reps = o.race_reps;
    m.timing.warmup = 1;
  }
  return s;
}

// A round that renders each candidate's still (its error) and times nothing.
void render_stills_only(sweep::SweepOptions& so) {
  so.measure.timing.reps = 1;
  so.measure.timing.warmup = 0;
  so.measure.timing.still_only = true;
}

// A measured backend's screen times its candidates a few rounds to cut the space down to what the race can
// time. When every candidate fits one batch of the race, the race makes that cut itself in its first rounds
// (a candidate a more accurate one beats stops after them, measure::Retire, with no flicker rendered), and
// scores the stills it retires by itself, before its warm-up and its rounds (TimingPlan::race_scores_stills):
// no screen runs. Not for shards, whose screens a join merges.
bool race_without_screen(const ShipOptions& o, int candidates) {
  return !estimated(o) && o.shard.count <= 1 && o.join.empty() && candidates <= batch_of(o) - 1;
}

// What a screen depends on beyond the fit: a join takes only shards whose screens had the same.
std::string screen_inputs(const Fitted& fit, const sweep::SweepOptions& so) {
  const measure::MeasureOptions& m = so.measure;
  const json inputs = {{"fit", fit.inputs},     {"calibration", m.calibration.hash},
                       {"globs", m.globs},      {"skip", m.skip},
                       {"views", m.views},      {"backends", m.backends},
                       {"size", fmt::format("{}x{}", m.size.width, m.size.height)},
                       {"reps", measure::reps_text(m)}, {"warmup", m.timing.warmup},
                       {"threads", m.scope.threads},  {"rays", m.truth.rays},
                       {"gpu", so.gpu.families}, {"gpu_frame", fmt::format("{}x{}", so.gpu.frame.width, so.gpu.frame.height)},
                       {"gpu_window", so.gpu.window}};
  return util::hash_hex(inputs.dump());
}

// One round's rows: its sweep; for the screen of a shard, that shard's share of it; for the screen of a
// join, the shards' screens merged.
table::CostTable round_rows(const ShipOptions& o, const Fitted& fit, const sweep::SweepOptions& so, bool final_round,
                            ShipResult& res, Round& r, const Progress& say) {
  const auto progress = [&](const std::string& line) {
    if (say) say(r.name + ": " + line);
  };
  if (final_round || (o.join.empty() && o.shard.count <= 1)) return sweep::run_sweep(so, progress).table;
  const std::string inputs = screen_inputs(fit, so);
  if (!o.join.empty()) {
    JoinedScreen joined = join_screens(o.join, inputs, so.out);
    r.timing += fmt::format(", {} shards joined", joined.shards);
    res.shard_balance = joined.balance;
    return std::move(joined.table);
  }
  record_input(o.out, "screen_inputs", inputs);
  sweep::SweepOptions shard = so;
  shard.shard = o.shard;
  sweep::SweepResult done = sweep::run_sweep(shard, progress);
  res.shard = o.shard.label();
  res.shard_balance = done.shard_balance;
  return std::move(done.table);
}

// The screen's still error of each candidate on each view it rendered, for the race to retire the beaten.
std::shared_ptr<const std::map<std::pair<std::string, std::string>, double>> still_errors(const table::CostTable& screen) {
  auto out = std::make_shared<std::map<std::pair<std::string, std::string>, double>>();
  for (const auto& r : screen.rows)
    if (r.error) (*out)[{r.variant, r.view}] = r.error->rmse;
  return out;
}

// The survivors' still errors on the held-out views (a sweep with no timing into OUT/holdout, resumable like
// every round) and which of them the held-out views time (holdout.h), recorded in `res`.
HoldoutPlan plan_holdout(const ShipOptions& o, const Fitted& fit, const std::vector<std::string>& survivors,
                         ShipResult& res, std::map<std::pair<std::string, std::string>, double>& errors, const Progress& say) {
  sweep::SweepOptions s = round_options(o, fit, res.holdout, survivors, {}, false);
  s.out = o.out / "holdout";
  render_stills_only(s);
  const table::CostTable stills =
      sweep::run_sweep(s, [&](const std::string& line) { say("race: held-out stills: " + line); }).table;
  HoldoutPlan plan = plan_holdout_timing(stills, survivors, o.query);
  const auto held_out = still_errors(stills);  // named: a range-for over *temporary would read a freed map (C++20)
  for (const auto& [at, rmse] : *held_out) errors[at] = rmse;
  res.holdout_rule = plan.rule;
  res.holdout_untimed = plan.untimed;
  return plan;
}

std::vector<std::string> variants_of(const table::CostTable& t) {
  std::set<std::string> keys;
  for (const auto& r : t.rows)
    if (r.error && !r.predicted) keys.insert(r.variant);
  return {keys.begin(), keys.end()};
}

// The race's rule on the training views of `rows`, deciding by `target`'s estimate (empty: the measured
// time): what it eliminates goes into `out` and res.eliminated (the budget's variant stays: select resolves
// the budget by it). A variant that runs the same code as an eliminated one (its rows are copies,
// same_code_as: no candidate of their own) goes with it; left in, it would be measured on its own in the next
// round.
void eliminate_dominated(const table::CostTable& rows, const ShipOptions& o, const std::string& target,
                         const std::string& round, std::set<std::string>& out, ShipResult& res) {
  std::vector<Elimination> now;
  for (auto& e : dominated_beyond_noise(table::rows_on_views(rows, res.training), target, o.race_margin))
    if (e.variant != o.query.budget_of && out.insert(e.variant).second) now.push_back(std::move(e));
  for (auto& e : same_code_eliminations(rows, now))
    if (e.variant != o.query.budget_of && out.insert(e.variant).second) now.push_back(std::move(e));
  for (auto& e : now) res.eliminated.push_back({round, std::move(e)});
}

// The measured backend's race with held-out views. The training views first: the rule looks at nothing else,
// so what it eliminates is never rendered on the held-out views. Then the held-out views, into the same
// folder, time only the survivors the query could choose (holdout.h), raced there by their held-out stills:
// one stops once a more accurate one is faster beyond the margin, or, with --budget-of (the baseline of every
// round), once the budget's variant is. The others keep their training rows. `candidates`: the round's,
// `out`: its eliminated.
table::CostTable race_then_holdout(const ShipOptions& o, const Fitted& fit, sweep::SweepOptions so, ShipResult& res,
                                   Round& r, std::set<std::string>& out, std::vector<std::string>& candidates,
                                   const Progress& say) {
  sweep::SweepOptions training = so;
  training.measure.views = res.training;
  table::CostTable last = round_rows(o, fit, training, true, res, r, say);
  candidates = variants_of(last);
  eliminate_dominated(last, o, "", r.name, out, res);
  std::erase_if(last.rows, [&](const table::CostRow& row) { return out.count(row.variant) > 0; });
  so.measure.globs.clear();  // the survivors by key (the race's globs may be patterns: no screen named them)
  for (const auto& k : candidates)
    if (!out.count(k)) so.measure.globs.push_back(k);
  auto errors = std::make_shared<std::map<std::pair<std::string, std::string>, double>>();
  if (so.measure.timing.race_errors) *errors = *so.measure.timing.race_errors;
  const HoldoutPlan plan = plan_holdout(o, fit, so.measure.globs, res, *errors, say);
  so.measure.views = res.holdout;
  so.measure.timing.race_errors = errors;
  so.measure.timing.race_scores_stills = false;  // the held-out stills are scored: plan_holdout
  so.measure.timing.race_budget = !o.query.budget_of.empty();
  decide::SelectQuery q = o.query;
  q.backend = o.backend;
  HoldoutTiming holdout = time_in_error_order(plan, q, [&](const std::vector<std::string>& keys) {
    so.measure.globs = keys;
    return round_rows(o, fit, so, true, res, r, say);
  });
  res.holdout_timed = int(holdout.timed);
  std::move(holdout.untimed.begin(), holdout.untimed.end(), std::back_inserter(res.holdout_untimed));
  std::move(holdout.rows.rows.begin(), holdout.rows.rows.end(), std::back_inserter(last.rows));
  return last;
}

// The query the held-out views answer: the user's, on the target's estimate or (target empty) the measured
// backend.
decide::SelectQuery final_query(const ShipOptions& o, const std::string& target) {
  decide::SelectQuery q = o.query;
  q.target = target;
  q.backend = o.backend;
  return q;
}

// meta.ship: every choice made, and the question the held-out views answered (`query`, the report asks it
// again of the table) with the line that builds the answer.
json ship_meta(const ShipOptions& o, const ShipResult& r, const profile::ScenePruning& pruning) {
  json rounds = json::array(), eliminated = json::array();
  for (const auto& x : r.rounds)
    rounds.push_back({{"name", x.name}, {"timing", x.timing}, {"candidates", x.candidates}, {"eliminated", x.eliminated},
                      {"seconds", x.seconds}});
  for (const auto& [round, e] : r.eliminated)
    eliminated.push_back({{"variant", e.variant}, {"round", round}, {"by", e.by}, {"reason", e.reason}});
  json untimed = json::array();
  for (const auto& u : r.holdout_untimed) untimed.push_back({{"variant", u.variant}, {"rmse", u.rmse}, {"reason", u.reason}});
  // Each target's question, and with several targets what survived on it (table::decided_rows reads both).
  json choices = json::array();
  for (const auto& c : r.choices) {
    json choice = {{"target", c.target}, {"query", decide::to_json(final_query(o, c.target))}};
    if (o.targets.size() > 1) choice["survivors"] = c.survivors;
    choices.push_back(std::move(choice));
  }
  return {{"scene", o.scene},
          {"training_views", r.training},
          {"holdout_views", r.holdout},
          {"targets", o.targets},
          {"backend", o.backend},
          {"race_margin", margin_in_force(o.targets.empty() ? "" : o.targets.front(), o.race_margin)},
          {"normals_lean", r.lean},
          {"normals_lean_evidence", r.lean_text},
          {"fit_normals", r.fit_normals},
          {"selected", r.selected},
          {"pruned", pruning.to_json(o.globs)},
          {"lean_dropped", r.lean_dropped},
          {"rounds", rounds},
          {"eliminated", eliminated},
          {"holdout_timing", {{"rule", r.holdout_rule}, {"timed", r.holdout_timed}, {"untimed", untimed}}},
          {"choices", choices},
          {"build_line", r.build_line}};
}

// Usage errors, before anything is profiled or fitted (an unknown family or a missing RADV too).
void check_options(const ShipOptions& o) {
  if (o.out.empty()) throw std::runtime_error("ship: --out is required");
  check_query(o.query);
  if (o.shard.count > 1 && !o.join.empty())
    throw std::runtime_error("ship: --shard and --join exclude each other (the shards screen, the join decides)");
  if (!o.join.empty()) check_join_folders(o.join, o.out);
  if (o.race_reps < 6) throw std::runtime_error("--race-reps must be at least 6 (fewer rounds give no 95 % interval)");
  if (o.batch != 0 && o.batch < 2) throw std::runtime_error("--batch must be at least 2 (the baseline and one candidate)");
  if (o.fit_evaluations < 1) throw std::runtime_error("--evaluations must be at least 1");

  if (!(o.race_margin >= 1.0 && o.race_margin < 10.0))
    throw std::runtime_error("--race-margin must be a time ratio in [1, 10) (1 eliminates on any slowdown beyond the noise)");
  if (estimated(o)) {
    gpu::check_gpus(o.targets);
    for (const auto& t : o.targets) {
      if (!gpu::estimate_spec(t)) throw std::runtime_error("--target " + gpu::validation_line(t));
      if (std::count(o.targets.begin(), o.targets.end(), t) > 1)
        throw std::runtime_error(fmt::format("ship: --target names {} twice", t));
    }
  }
}

// --budget-of resolved before anything renders (issue 54: a key nobody has profiled, fitted, raced and timed
// before it failed): one variant key, of this manifest's space after its rules, among --variants.
void check_budget_of(const ShipOptions& o) {
  const std::string& key = o.query.budget_of;
  if (key.empty()) return;
  if (key.find_first_of("*?[") != std::string::npos)
    throw std::runtime_error(fmt::format("ship: --budget-of '{}' is a pattern: give one variant key (aovar list "
                                         "prints them)", util::one_line(key)));
  const variants::VariantSpace space = variants::build_space(o.scope.manifest.get(), {key});
  if (std::none_of(space.variants.begin(), space.variants.end(), [&](const auto& v) { return v.key == key; }))
    throw std::runtime_error(fmt::format("ship: --budget-of '{}' is no variant of {} after its rules: give a key "
                                         "aovar list prints",
                                         util::one_line(key), util::display_path(o.scope.manifest.path())));
  if (!o.globs.empty() && !util::glob_any(o.globs, key))
    throw std::runtime_error(fmt::format("ship: --budget-of '{}' is outside --variants: the race must time the "
                                         "budget's variant; add it to --variants",
                                         util::one_line(key)));
}

// The measured backend's search: a screen of every candidate (unless one race batch holds them all), the
// dominated eliminated, then the race over the survivors with the held-out views (race_then_holdout).
table::CostTable measured_search(const ShipOptions& o, const Fitted& fit, const std::vector<std::string>& views,
                                 std::vector<std::string> globs, const std::set<std::string>& skip, ShipResult& res,
                                 const Progress& say) {
  const bool no_screen = race_without_screen(o, res.selected - int(skip.size()));
  table::CostTable last;
  for (const bool final_round : {false, true}) {
    if (!final_round && no_screen) continue;
    Round r;
    r.name = round_name(false, final_round);
    const auto t0 = std::chrono::steady_clock::now();
    // The screen decides on the training views only (its eliminations look at nothing else), so it renders
    // nothing else; the survivors are measured on every view, the held-out one for the choice.
    sweep::SweepOptions so = round_options(o, fit, final_round ? views : res.training, globs, skip, final_round);
    // The race times a view's beaten candidates no longer than it must: one stops once a more accurate one of
    // its batch (in the same rounds) or of an earlier batch (against the same reference) is faster beyond the
    // noise. It is off the front then, whatever more rounds would show; whether it leaves the table is the
    // elimination's call, with --race-margin, after the round. The screen's front is timed first (screen_ranks).
    if (final_round) {
      if (no_screen) {
        so.measure.timing.race_scores_stills = true;
      } else {
        so.measure.timing.race_errors = still_errors(last);
        so.measure.timing.race_order = screen_ranks(last);
      }
      so.measure.timing.race_margin = kRetireMargin;
    }
    r.timing = final_round ? measure::reps_words(so.measure) : fmt::format("{} reps", so.measure.timing.reps);
    if (!final_round) r.timing += ", still error only";
    if (no_screen) r.timing += "; no screen: one batch holds every candidate, the race scores their stills";
    const std::string what = final_round && !no_screen ? fmt::format("{} survivors", globs.size())
                             : o.globs.empty()         ? std::string("the whole pruned space")
                                                       : std::string("the selection");
    say(fmt::format("round {}: {} ({})", r.name, what, r.timing));
    std::set<std::string> out;            // this round's eliminated
    std::vector<std::string> candidates;  // this round's candidates
    if (final_round && !res.holdout.empty())
      last = race_then_holdout(o, fit, so, res, r, out, candidates, say);
    else
      last = round_rows(o, fit, so, final_round, res, r, say);
    if (!res.shard.empty()) {  // a shard screens its share and stops: the join eliminates and selects
      r.candidates = int(variants_of(last).size());
      r.seconds = util::seconds_since(t0);
      res.rounds.push_back(r);
      return last;
    }
    if (candidates.empty()) candidates = variants_of(last);
    eliminate_dominated(last, o, "", r.name, out, res);
    r.candidates = int(candidates.size());
    r.eliminated = int(out.size());
    r.seconds = util::seconds_since(t0);
    res.rounds.push_back(r);
    globs.clear();
    for (const auto& k : candidates)
      if (!out.count(k)) globs.push_back(k);
    std::erase_if(last.rows, [&](const table::CostRow& row) { return out.count(row.variant) > 0; });
  }
  res.choices.push_back({"", globs, {}});
  return last;
}

// Views in turn (issue 55): an unsharded screen with several training views renders every candidate on the
// first one only; the others are rendered for the candidates the bounded estimate cannot drop on that view's
// error (bounded_estimate.h), a chunk at a time, each chunk one measurement into OUT/screen-views/<n> (resumable:
// the chunks come in the same order again). A chunk rendered for one target serves the later ones. Only the
// stills' errors are wanted: no static analysis, model, table or report per chunk (sweep::measure_rows); the
// static cost, which the view does not change, is the first view's row's.
class OtherViews {
 public:
  // `first`: the first view's rows, whose copies (same_code_as, measure/same_code.h) must stay copies.
  OtherViews(const ShipOptions& o, const Fitted& fit, const ShipResult& res, const std::set<std::string>& skip,
             const table::CostTable& first, const Progress& say, ReferencePrefetch* prefetch)
      : o_(o), fit_(fit), views_(res.training.begin() + 1, res.training.end()), skip_(skip), say_(say),
        prefetch_(prefetch) {
    for (const auto& r : first.rows) {
      if (!r.same_code_as.empty()) copy_of_[r.variant] = r.same_code_as;
      static_of_.emplace(r.variant, r.static_cost);
    }
  }

  std::vector<table::CostRow> render(const std::vector<std::string>& keys) {
    std::vector<std::string> todo;
    for (const auto& k : keys)
      if (!rows_.count(k)) todo.push_back(k);
    if (!todo.empty()) {
      // A copy's representative renders with it, so that the copy is one again: the race counts a copy's rows
      // as its representative's (race.h), and a copy measured on one view only would be judged on that view.
      std::set<std::string> globs(todo.begin(), todo.end());
      for (const auto& k : todo)
        if (auto it = copy_of_.find(k); it != copy_of_.end()) globs.insert(it->second);
      sweep::SweepOptions so = round_options(o_, fit_, views_, {globs.begin(), globs.end()}, skip_, false);
      so.out = o_.out / "screen-views" / std::to_string(sweeps_++);
      // The first key as the baseline: no extra render (stills only), and every group of copies keeps its first
      // key as representative (group_twins keeps the baseline's group's baseline), as the first view did.
      so.measure.baseline = *globs.begin();
      const std::set<std::string> wanted(todo.begin(), todo.end());
      const auto progress = [&](const std::string& line) {
        if (say_) say_("screen: other views: " + line);
      };
      if (prefetch_) prefetch_->wait_for(views_);  // their references: traced during the screen
      for (table::CostRow& row : sweep::measure_rows(so, progress))
        if (wanted.count(row.variant)) {
          if (auto it = static_of_.find(row.variant); it != static_of_.end()) row.static_cost = it->second;
          rows_[row.variant].push_back(std::move(row));
        }
      rendered_ += int(todo.size());
    }
    std::vector<table::CostRow> out;
    for (const auto& k : keys) {
      auto it = rows_.find(k);
      if (it != rows_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
    }
    return out;
  }
  int rendered() const { return rendered_; }

 private:
  const ShipOptions& o_;
  const Fitted& fit_;
  std::vector<std::string> views_;
  const std::set<std::string>& skip_;
  const Progress& say_;
  ReferencePrefetch* prefetch_;
  std::map<std::string, std::vector<table::CostRow>> rows_;
  std::map<std::string, std::string> copy_of_;
  std::map<std::string, std::optional<table::StaticCost>> static_of_;
  int sweeps_ = 0, rendered_ = 0;
};

bool views_in_turn(const ShipOptions& o, const ShipResult& res) {
  return res.training.size() > 1 && o.shard.count <= 1 && o.join.empty();
}

// The GPU targets' screen: one render of every candidate's still (its error is the same on every GPU; on the
// first training view only when views_in_turn), then per target the estimate in order of error
// (bounded_estimate.h) and the race's rule on it. res.choices gets each target's survivors; returns the
// screen's rows.
table::CostTable estimated_screen(const ShipOptions& o, const Fitted& fit, const std::vector<std::string>& views,
                                  const std::vector<std::string>& globs, const std::set<std::string>& skip,
                                  ShipResult& res, const Progress& say, ReferencePrefetch* prefetch) {
  Round r;
  r.name = round_name(true, false);
  const auto t0 = std::chrono::steady_clock::now();
  const bool in_turn = views_in_turn(o, res);
  sweep::SweepOptions so = round_options(o, fit, in_turn ? std::vector{res.training.front()} : res.training, globs,
                                         skip, false);
  r.timing = fmt::format("one render, estimate on {}, still error only", fmt::join(o.targets, ", "));
  if (in_turn) r.timing += fmt::format("; views in turn: {} first", res.training.front());
  say(fmt::format("round {}: {} ({})", r.name, o.globs.empty() ? "the whole pruned space" : "the selection", r.timing));
  const table::CostTable screen = round_rows(o, fit, so, false, res, r, say);
  r.candidates = int(variants_of(screen).size());
  OtherViews other_views(o, fit, res, skip, screen, say, prefetch);
  RenderRest render_rest;
  if (in_turn) render_rest = [&](const std::vector<std::string>& keys) { return other_views.render(keys); };
  if (res.shard.empty()) {  // a shard screens its share and stops: the join estimates, eliminates and selects
    std::set<std::string> kept;  // what survived on some target
    std::vector<std::string> traced;
    for (const std::string& target : o.targets) {
      sweep::SweepOptions estimated = round_options(o, fit, views, globs, skip, true);
      estimated.gpu.families = {target};
      table::CostTable rows = screen;
      BoundedEstimate b =
          estimate_in_error_order(rows, res.training, measure::gpu_request(estimated.measure, estimated.gpu),
                                  o.query.budget_of, [&](const std::string& line) { say(r.name + ": " + line); }, 16,
                                  render_rest);
      for (auto& e : b.eliminated) res.eliminated.push_back({round_on(r.name, o, target), std::move(e)});
      std::string count = std::to_string(b.traced);
      if (b.first_view_traced > b.traced) count += fmt::format(" (and {} on the first view only)", b.first_view_traced - b.traced);
      traced.push_back(o.targets.size() > 1 ? fmt::format("{} {}", target, count) : count);
      std::set<std::string> out;
      const std::vector<std::string> candidates = variants_of(rows);
      eliminate_dominated(rows, o, target, round_on(r.name, o, target), out, res);
      ShipChoice choice{target, {}, {}};
      for (const auto& k : candidates)
        if (!out.count(k)) choice.survivors.push_back(k), kept.insert(k);
      res.choices.push_back(std::move(choice));
    }
    r.eliminated = r.candidates - int(kept.size());
    r.timing += fmt::format(", traced in order of error: {}", fmt::join(traced, ", "));
    if (in_turn)
      r.timing += fmt::format(", {} of {} rendered on the other training views", other_views.rendered(), r.candidates);
  }
  r.seconds = util::seconds_since(t0);
  res.rounds.push_back(r);
  return screen;
}

// The GPU targets' search: the screen (estimated_screen), then one front round that renders the union of the
// targets' survivors on every view with every target's estimate, and per target the race's rule again among
// its own survivors. With one target this is exactly the single-target search; with several, each target's
// survivors are those its own search would keep.
table::CostTable estimated_search(const ShipOptions& o, const Fitted& fit, const std::vector<std::string>& views,
                                  const std::vector<std::string>& globs, const std::set<std::string>& skip,
                                  ShipResult& res, const Progress& say) {
  // What the rounds after the screen ray-trace first, traced in its idle time: the other training views'
  // references (views in turn renders them after the first view's estimate), and the held-out views'.
  std::optional<ReferencePrefetch> prefetch;
  if (o.shard.count <= 1) {
    std::vector<std::string> later = res.holdout;
    if (views_in_turn(o, res)) later.insert(later.begin(), res.training.begin() + 1, res.training.end());
    measure::MeasureOptions front = round_options(o, fit, views, {}, skip, true).measure;
    front.truth.enabled = true;  // as every round's sweep scores (sweep::plan_scenes)
    prefetch.emplace(front, o.scene, later);
  }
  const table::CostTable screen = estimated_screen(o, fit, views, globs, skip, res, say, prefetch ? &*prefetch : nullptr);
  if (!res.shard.empty()) return screen;
  if (prefetch) prefetch->wait_for(res.holdout);
  Round r;
  r.name = round_name(true, true);
  r.timing = "one render, estimate on " + fmt::format("{}", fmt::join(o.targets, ", "));
  const auto t0 = std::chrono::steady_clock::now();
  std::set<std::string> union_of;
  for (const auto& c : res.choices) union_of.insert(c.survivors.begin(), c.survivors.end());
  const std::vector<std::string> survivors(union_of.begin(), union_of.end());
  say(fmt::format("round {}: {} survivors ({})", r.name, survivors.size(), r.timing));
  table::CostTable last = round_rows(o, fit, round_options(o, fit, views, survivors, skip, true), true, res, r, say);
  r.candidates = int(variants_of(last).size());
  std::set<std::string> kept;
  for (ShipChoice& c : res.choices) {
    table::CostTable mine = last;
    const std::set<std::string> own(c.survivors.begin(), c.survivors.end());
    std::erase_if(mine.rows, [&](const table::CostRow& row) { return !own.count(row.variant); });
    std::set<std::string> out;
    const std::vector<std::string> candidates = variants_of(mine);
    eliminate_dominated(mine, o, c.target, round_on(r.name, o, c.target), out, res);
    c.survivors.clear();
    for (const auto& k : candidates)
      if (!out.count(k)) c.survivors.push_back(k), kept.insert(k);
  }
  r.eliminated = r.candidates - int(kept.size());
  r.seconds = util::seconds_since(t0);
  res.rounds.push_back(r);
  std::erase_if(last.rows, [&](const table::CostRow& row) { return !kept.count(row.variant); });
  return last;
}

// The choice on each target: select among its survivors on the held-out views, with table::decided_rows's
// rule (the report and `generate --from-table` read the table back with it).
void choose(const ShipOptions& o, ShipResult& res) {
  const table::CostTable held_out = table::rows_on_views(res.table, res.holdout);
  for (ShipChoice& c : res.choices) {
    table::CostTable mine = held_out;
    const std::set<std::string> own(c.survivors.begin(), c.survivors.end());
    std::erase_if(mine.rows, [&](const table::CostRow& row) { return !own.count(row.variant); });
    c.selection = decide::select(mine, final_query(o, c.target));
  }
}

// The query as generate's options.
std::string query_options(const decide::SelectQuery& q) {
  if (!q.budget_of.empty()) return "--budget-of " + util::shell_quote(q.budget_of);
  if (q.budget_ms) return fmt::format("--budget-ms {}", *q.budget_ms);
  return fmt::format("--max-error {}", q.max_error.value_or(0));
}

// The line that builds what to ship, carrying the fit: the generated library holds the values the choice was
// scored with. One choice: exactly that variant. Several GPUs: one library from this table whose pick()
// serves each GPU its choice (generate --from-table keeps, per target, select's answer on the rows it was
// decided on).
std::string build_line_of(const ShipOptions& o, const Fitted& fit, const ShipResult& res) {
  const std::string manifest = util::display_path(o.scope.manifest.path());
  if (res.choices.size() > 1) {
    for (const auto& c : res.choices)
      if (!c.selection.choice) return "";
    return fmt::format("aovar generate --manifest {} --from-table {} --for {} {} --out shaders", manifest,
                       util::display_path(o.out / "cost_table.json"), fmt::join(o.targets, ","), query_options(o.query));
  }
  if (res.choices.empty() || !res.choices.front().selection.choice) return "";
  return fmt::format("aovar generate --manifest {} --variants '{}'{} --out shaders", manifest,
                     res.choices.front().selection.choice->variant,
                     fit.calibration.file.empty() ? "" : " --calibration " + fit.calibration.file);
}

// Several targets' choices, a line each: the GPU, its choice, its estimate and held-out error.
std::string choices_side_by_side(const std::vector<ShipChoice>& choices) {
  std::size_t target_width = 6, key_width = 6;
  for (const auto& c : choices) {
    target_width = std::max(target_width, c.target.size());
    if (c.selection.choice) key_width = std::max(key_width, c.selection.choice->variant.size());
  }
  std::string s = fmt::format("{:<{}}  {:<{}}  {:>10}  {:>9}  {}\n", "target", target_width, "choice", key_width, "estimate",
                              "rmse", "survivors");
  for (const auto& c : choices) {
    if (!c.selection.choice) {
      s += fmt::format("{:<{}}  nothing fits: {}\n", c.target, target_width, c.selection.reason);
      continue;
    }
    const decide::Candidate& x = *c.selection.choice;
    s += fmt::format("{:<{}}  {:<{}}  {:>7.3f} ms  {:>9.5f}  {}\n", c.target, target_width, x.variant, key_width, x.time_ms,
                     x.rmse, c.survivors.size());
  }
  return s;
}

}  // namespace

int batch_for(render::Extent size) {
  const double pixels = double(size.width) * size.height, reference = 640.0 * 360.0;
  return std::clamp(int(128 * reference / std::max(pixels, reference)), 24, 128);
}

ShipResult run_ship(const ShipOptions& o, const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  check_options(o);
  check_budget_of(o);
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  ShipResult res;
  scene::LoadOptions lo;
  lo.views_file = o.views_file;
  const scene::Scene sc = scene::load_scene(o.scene, lo);
  const calibrate::ViewSplit split = calibrate::split_views({o.scene}, o.views_file, {}, o.holdout_views, "ship");
  for (const auto& v : split.training) res.training.push_back(v.view);
  for (const auto& v : split.holdout) res.holdout.push_back(v.view);
  std::vector<std::string> views = res.training;
  views.insert(views.end(), res.holdout.begin(), res.holdout.end());

  // 1. The profile of every view: its pruning and the normals lean.
  say("profiling " + o.scene);
  const variants::Manifest& manifest = o.scope.manifest.get();
  const ProfiledSpace profiled = profile_space(o, sc, views, manifest, res, say);

  // 2. The methods fitted on the training views.
  say(fmt::format("fitting the methods on {} (normals: {})", fmt::join(res.training, ", "), res.fit_normals));
  const Fitted fit = fit_methods(o, sc, split, res.fit_normals, manifest, progress);

  // 3. The search over the pruned space: rounds, the dominated eliminated after each.
  const std::vector<std::string> globs = o.globs.empty() ? std::vector<std::string>{"*"} : o.globs;
  table::CostTable last = estimated(o) ? estimated_search(o, fit, views, globs, profiled.skip, res, say)
                                       : measured_search(o, fit, views, globs, profiled.skip, res, say);
  if (!res.shard.empty()) {
    res.wall_s = util::seconds_since(start);
    return res;
  }

  // 4. Select among the survivors on the held-out views.
  decide::mark_pareto(last);
  res.table = std::move(last);
  choose(o, res);
  res.build_line = build_line_of(o, fit, res);
  res.table.meta.ship = ship_meta(o, res, profiled.pruning);
  table::write_table_files(res.table, o.out);
  report::write_reports(res.table, o.out, o.out / round_name(estimated(o), true), manifest.algorithms);
  res.wall_s = util::seconds_since(start);
  return res;
}

std::string to_text(const ShipResult& r, const ShipOptions& o) {
  std::string s = fmt::format("scene {}: trained on {}, held out {}\n", o.scene, fmt::join(r.training, ", "),
                              fmt::join(r.holdout, ", "));
  s += fmt::format("normals: {}; {} -> search {}normals, fit with normals = {}\n", r.lean_text,
                   r.lean ? "a lean" : "no lean", r.lean ? "depth " : "every source of ", r.fit_normals);
  s += fmt::format("space: {} selected, {} dropped by the profile, {} by the lean\n", r.selected, r.pruned, r.lean_dropped);
  if (!estimated(o))
    s += fmt::format("race margin: eliminated only when slower beyond {:.2f}x (the 95 % interval's low end; --race-margin)\n",
                     o.race_margin);
  for (const auto& x : r.rounds)
    s += fmt::format("round {}: {} candidates ({}), {} eliminated, {:.0f} s\n", x.name, x.candidates, x.timing, x.eliminated,
                     x.seconds);
  if (!r.holdout_rule.empty())
    s += fmt::format("held-out view{}: timed {} of {} survivors, {}; the rest cannot be chosen (meta.ship.holdout_timing)\n",
                     r.holdout.size() > 1 ? "s" : "", r.holdout_timed, r.holdout_timed + int(r.holdout_untimed.size()),
                     r.holdout_rule);
  if (!r.shard.empty())
    return s + fmt::format("shard {}: {}; {}/screen/shard.json written. When every shard is done, join them "
                           "(with the same options): aovar ship ... --join SHARD_FOLDER... --out DIR\n",
                           r.shard, r.shard_balance, util::display_path(o.out));
  if (!r.shard_balance.empty()) s += "shards joined: " + r.shard_balance + "\n";
  s += "\nWhat to ship (selected on the held-out view" + std::string(r.holdout.size() > 1 ? "s" : "") + "):\n";
  if (r.choices.size() > 1) s += choices_side_by_side(r.choices) + "\n";
  for (const auto& c : r.choices) {
    if (r.choices.size() > 1) s += "on " + c.target + ":\n";
    s += c.selection.text;
    if (!c.target.empty()) s += "estimate on " + gpu::validation_line(c.target) + "\n";
  }
  if (!r.build_line.empty()) s += "build it: " + r.build_line + "\n";
  s += fmt::format("cost table and report: {}/cost_table.json, {}/report.html ({:.0f} s)\n", util::display_path(o.out),
                   util::display_path(o.out), r.wall_s);
  return s;
}

}  // namespace aovar::ship
