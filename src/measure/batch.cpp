#include "measure/batch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>

#include <fmt/format.h>

#include "image/image.h"
#include "measure/same_code.h"
#include "render/gbuffer_share.h"
#include "shadergen/expand.h"
#include "util/clock.h"
#include "util/hash.h"
#include "util/in_order.h"
#include "util/intervals.h"
#include "util/path_names.h"

namespace aovar::measure {
namespace fs = std::filesystem;
using json = nlohmann::json;
using util::Clock;
using util::seconds_since;

namespace {
std::string size_text(render::Extent e) { return fmt::format("{}x{}", e.width, e.height); }

// An id no other batch shares, in this run or an earlier one whose rows are reused next to these: rows with
// the same id are paired round by round (decide/time_compare.h).
std::string batch_id(const std::string& where, int batch) {
  util::Hasher h;
  h.add(where).add(std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()))
      .add(std::to_string(std::chrono::system_clock::now().time_since_epoch().count()));
  return fmt::format("{}/{}", h.hex().substr(0, 12), batch);
}

// The view's candidates in the race's order (TimingPlan::race_order): lower rank first, unranked last.
template <typename Candidate>
void order_for_race(std::vector<Candidate>& todo, const TimingPlan& timing, const std::string& view) {
  if (!timing.race_order) return;
  const auto rank = [&](const Candidate& c) {
    auto it = timing.race_order->find({c.plan.variant, view});
    return it == timing.race_order->end() ? std::numeric_limits<int>::max() : it->second;
  };
  std::stable_sort(todo.begin(), todo.end(), [&](const Candidate& a, const Candidate& b) { return rank(a) < rank(b); });
}

// Without a race order: the candidates that read one G-buffer (render/gbuffer_share.h) next to each other, groups
// in order of first appearance. Each round draws every G-buffer its batch reads once (measure/timing.h), so a
// batch of few formats rasterises the scene few times, whatever its size.
template <typename Candidate>
void order_by_gbuffer(std::vector<Candidate>& todo, const TimingPlan& timing, render::Extent size) {
  if (timing.race_order) return;
  std::map<std::string, std::size_t> group;  // G-buffer key -> order of first appearance
  std::vector<std::size_t> group_of;
  for (const Candidate& c : todo) {
    const auto split = render::split_gbuffer(c.plan, size);  // a G-buffer has one level: no plan_for_size copy
    group_of.push_back(group.emplace(split ? split->key : c.plan.variant, group.size()).first->second);
  }
  std::vector<std::size_t> order(todo.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return group_of[a] < group_of[b]; });
  std::vector<Candidate> sorted;
  sorted.reserve(todo.size());
  for (std::size_t i : order) sorted.push_back(std::move(todo[i]));
  todo = std::move(sorted);
}

// What a timed batch leaves for the later ones to retire against (Retire::earlier): each pipeline but the
// reference with a known error and a known interval against it.
void add_earlier_rows(std::vector<EarlierRow>& earlier, const Retire& rule, const RoundRobinResult& timed) {
  for (std::size_t i = 1; i < timed.pipelines.size() && i < rule.known_error.size(); ++i) {
    const util::Interval ci = util::median_interval(round_ratios(timed.pipelines[i], timed.pipelines[0]));
    if (std::isfinite(rule.known_error[i]) && ci.known()) earlier.push_back({rule.known_error[i], ci.hi});
  }
}
}  // namespace

BatchMeasurer::BatchMeasurer(const MeasureOptions& options, const compile::CompiledSpace& compiled,
                             const scene::Scene& scene, const Selection& selection, const PreviousRun& earlier,
                             MeasureResult& result, const Progress& progress)
    : o_(options), c_(compiled), scene_(scene), sel_(selection), earlier_(earlier), res_(result), progress_(progress) {}

std::map<std::string, json> BatchMeasurer::unproduced_rows(const std::vector<const scene::View*>& views) const {
  std::set<std::string> produced;
  for (int v : sel_.measured) produced.insert(c_.space.variants[v].key);
  produced.insert(c_.space.variants[sel_.baseline].key);
  std::map<std::string, json> kept;
  for (const auto& entry : earlier_.rows) {  // not a structured binding: clang 14 cannot capture one
    const auto& [hash, r] = entry;
    const std::string& view = r.view;
    if (!produced.count(r.variant) ||
        std::find(o_.backends.begin(), o_.backends.end(), r.backend) == o_.backends.end() ||
        std::none_of(views.begin(), views.end(), [&](const scene::View* v) { return v->name == view; }))
      kept.emplace(hash, earlier_.text.at(hash));
  }
  return kept;
}

// Progress: rows done out of rows wanted, and an ETA from the time per measured (not reused) row. Rows finish a
// batch at a time: the rate is taken at the last finished row, and the time since then counts down the rest, so
// the ETA does not climb while a batch is under way (it used to: elapsed time over a row count that stood still).
void BatchMeasurer::status(const std::string& what) const {
  if (!progress_) return;
  std::string eta;
  std::size_t done = res_.rows.size();
  if (rows_measured_ > 0 && done < rows_wanted_) {
    const double per_row = std::chrono::duration<double>(last_measured_ - measuring_start_).count() /
                           static_cast<double>(rows_measured_);
    const double rest = per_row * static_cast<double>(rows_wanted_ - done) - seconds_since(last_measured_);
    auto left = static_cast<long>(std::max(0.0, rest));
    eta = fmt::format(", ETA {}m{:02}s", left / 60, left % 60);
  }
  progress_(fmt::format("[{}/{} rows{}] {}", done, rows_wanted_, eta, what));
}

// Ground truth: one ray-traced reference per view, at the measured size, radius and camera pose (the last
// frame of the path with --camera-path, as the images are), shared by every backend and variant. Its cache
// key (scene, camera, size, radius, rays, mode) is part of every row's inputs; the image itself is traced
// (or loaded from the cache) only for a view with rows to measure, or whose copy under images/reference/ is
// missing, so a repeated run traces nothing.
const reference::ReferenceImage& BatchMeasurer::ground_truth(const scene::View& view) {
  if (auto it = truth_.find(view.name); it != truth_.end()) return it->second;
  auto ref = reference::trace_reference(scene_, view, measure::reference_options(o_, res_.radius), [&](double f, double elapsed) {
    if (progress_)
      progress_(fmt::format("reference {}: {:.0f} %{}", view.name, 100 * f,
                            f > 0.01 ? fmt::format(", ETA {:.0f} s", elapsed * (1 - f) / f) : std::string()));
  });
  if (!o_.out.empty() && o_.images) {
    util::check_path_component(view.name, "view name");
    reference::write_reference(o_.out / "images" / "reference" / view.name, ref);
  }
  return truth_.emplace(view.name, std::move(ref)).first->second;
}

const runner::ViewScorer& BatchMeasurer::scorer(const scene::View& view) {
  if (auto it = scorers_.find(view.name); it != scorers_.end()) return it->second;
  return scorers_.try_emplace(view.name, ground_truth(view), view, res_.radius).first->second;
}

void BatchMeasurer::store_references(const std::vector<const scene::View*>& views) {
  for (const scene::View* view : views)
    if (!fs::exists(o_.out / "images" / "reference" / (view->name + ".pfm"))) ground_truth(*view);
}

// Every input of a row but the variant's own (programs, key, plan: variant_inputs). The selection and --batch
// are not inputs: the paired time (ratio to the baseline in the same rounds) cancels the drift between runs,
// so rows measured in different runs, or a sweep's pruning phases, combine. The device and driver are
// inputs: a row timed on one device (--device) is never reused for another.
std::string BatchMeasurer::context(const runner::VariantRunner& runner, const scene::View& view) const {
  const auto& info = runner.device();
  std::string context = fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", shadergen::generator_version(),
                                    scene_.content_hash, scene::camera_text(view), info.backend, info.device,
                                    info.driver, info.mediump_fp16, size_text(o_.size), o_.scope.threads, reps_text(o_), o_.timing.warmup,
                                    res_.radius, c_.space.variants[sel_.baseline].key);
  if (o_.timing.camera_path) context += "|path";
  if (!o_.truth.temporal) context += "|still";  // a row without flicker is not one with it
  if (o_.truth.enabled) context += "|truth:" + reference::cache_key(scene_, view, measure::reference_options(o_, res_.radius));
  return context;
}

BatchMeasurer::Candidate BatchMeasurer::candidate(runner::VariantRunner& runner, int v, const std::string& context) const {
  Candidate cand{v, runner.plan(v, o_.params, false), {}};
  cand.inputs = variant_inputs(c_, v, c_.target_index(runner.target()), cand.plan, context);
  return cand;
}

MeasureRow BatchMeasurer::new_row(const Candidate& cand, const render::DeviceInfo& device, const std::string& view) const {
  MeasureRow row;
  row.variant = cand.plan.variant;
  row.axes = cand.plan.axes;
  if (auto d = sel_.duplicates.find(cand.variant); d != sel_.duplicates.end()) row.duplicates = d->second;
  row.scene = res_.scene;
  row.backend = device.backend;
  row.device = device.device;
  row.driver = device.driver;
  row.view = view;
  row.size = size_text(o_.size);
  row.threads = o_.scope.threads;
  row.spirv_hash = cand.inputs.spirv_hash;
  row.inputs_hash = cand.inputs.inputs_hash;
  row.baseline = c_.space.variants[sel_.baseline].key;
  row.rounds.scale = fmt::format("{}@{}/{}/{}/{}/{}/{}", row.baseline, row.scene, row.view, row.backend, row.device,
                                 row.size, row.threads);
  return row;
}

// A row whose inputs are unchanged comes from the earlier run. What belongs to this run rather than to the
// measurement (another selection lists other duplicates, and the baseline's row is timing-only when no glob
// selects it) is taken from this run.
bool BatchMeasurer::reuse(const Candidate& cand, const render::DeviceInfo& device, const std::string& view) {
  auto it = earlier_.rows.find(cand.inputs.inputs_hash);
  if (it == earlier_.rows.end() || !it->second.same_code_as.empty()) return false;  // a copy is no measurement
  MeasureRow row = it->second;
  row.duplicates = new_row(cand, device, view).duplicates;
  row.device = device.device;  // the inputs hash holds device and driver: the same ones, also for rows
  row.driver = device.driver;  // written before rows carried them
  row.is_baseline = cand.variant == sel_.baseline && !sel_.baseline_selected;
  res_.rows.push_back(std::move(row));
  ++res_.reused;
  return true;
}

void BatchMeasurer::measure_all(const std::vector<const scene::View*>& views, const std::function<void()>& after_batch) {
  rows_wanted_ = (sel_.measured.size() + (sel_.baseline_selected ? 0 : 1)) * views.size() * o_.backends.size();
  measuring_start_ = last_measured_ = Clock::now();
  for (const auto& backend_name : o_.backends) {
    runner::RunnerOptions ro;
    ro.backend = backend_name;
    ro.device.threads = o_.scope.threads;
    ro.device.device = o_.device;
    ro.device.share_gbuffer = o_.share_gbuffer;
    ro.device.gbuffer_cache = o_.scope.cache_dir;  // stills upload a stored G-buffer (render::GbufferStore)
    ro.size = o_.size;
    ro.calibration = o_.calibration.values;
    runner::VariantRunner runner(c_, ro);
    res_.devices.push_back(runner.device());
    runner.use_scene(scene_);
    StillDevices devices{&runner, ro, {}};
    for (const scene::View* view : views) measure_view(devices, *view, after_batch);
  }
}

runner::VariantRunner& BatchMeasurer::StillDevices::at(std::size_t i, const scene::Scene& scene) {
  if (i == 0) return *first;
  while (more.size() < i) {
    more.push_back(std::make_unique<runner::VariantRunner>(first->compiled(), options));
    more.back()->use_scene(scene);
  }
  return *more[i - 1];
}

// How many devices render this view's batches (TimingPlan::still_devices): more than one only for stills on a
// backend that runs side by side, and never more than there are batches.
std::size_t BatchMeasurer::still_devices(const runner::VariantRunner& runner, int batches) const {
  if (!o_.timing.still_only || o_.timing.races() || o_.timing.still_devices <= 1 ||
      !render::backend_info(runner.device().backend).side_by_side)
    return 1;  // a race reads the batches before (Retire::earlier): one device, in order
  return static_cast<std::size_t>(std::min(o_.timing.still_devices, batches));
}

// Prepares todo[lo, hi) on `runner` and renders them with the baseline's pipeline `ref_pipeline` of the same
// runner: the stills, or the warm-up and the timed rounds; then their rows, finished against the batch's
// baseline. `report`: status lines (only the thread that owns the progress callback).
BatchMeasurer::BatchRows BatchMeasurer::run_batch(runner::VariantRunner& runner, render::PreparedPipeline& ref_pipeline,
                                                  const Candidate& ref, const std::vector<Candidate>& todo,
                                                  std::size_t lo, std::size_t hi, const scene::View& view,
                                                  const std::string& where, TimingOptions& to, bool report) {
  const auto prep_start = Clock::now();
  BatchRows out;
  out.run = RunRecord{runner.device().backend, view.name, static_cast<int>(hi - lo) + 1};
  std::vector<std::unique_ptr<render::PreparedPipeline>> prepared;
  std::vector<render::PreparedPipeline*> pointers{&ref_pipeline};
  std::vector<int> still_frames{ref.plan.progressive ? 2 : 1};  // both halves of a progressive still
  for (std::size_t i = lo; i < hi; ++i) {
    if (report) status(fmt::format("{}: preparing {}", where, todo[i].plan.variant));
    prepared.push_back(runner.prepare(todo[i].plan));
    pointers.push_back(prepared.back().get());
    still_frames.push_back(todo[i].plan.progressive ? 2 : 1);
  }
  out.run.prepare_s = seconds_since(prep_start);
  out.timed = render_batch(runner, pointers, still_frames, view, to, where, report);
  out.run.warmup_s = out.timed.wall_warmup_s;
  out.run.timed_wall_s = out.timed.wall_timed_s;
  out.run.timed_sum_s = out.timed.sum_timed_s;

  const auto read_start = Clock::now();
  const PipelineTiming& batch_ref = out.timed.pipelines[0];
  const double ref_min = util::summarize(batch_ref.total_ms).min;
  for (std::size_t i = lo; i < hi; ++i) {
    const PipelineTiming& timing = out.timed.pipelines[i - lo + 1];
    MeasureRow row = new_row(todo[i], runner.device(), view.name);
    finish_row(row, runner, todo[i], *prepared[i - lo], timing, view);
    row.rel_time = ref_min > 0 ? row.time_ms.min / ref_min : 0;
    row.rel_time_median = median_ratio(timing, batch_ref);
    row.rounds.ratios = round_ratios(timing, batch_ref);  // the id: measure_view's, when it keeps the batch
    row.set_reps_reached(timing.stop);
    out.rows.push_back(std::move(row));
  }
  out.run.readback_s = seconds_since(read_start);
  return out;
}

// Reuse rows whose inputs are unchanged; everything else is measured in batches with the baseline, which is
// re-measured whenever anything else is (rel_time needs it in the same rounds). Stills may render on several
// devices (still_devices); the rows, the checkpoints and the baseline's row come in batch order either way.
void BatchMeasurer::measure_view(StillDevices& devices, const scene::View& view, const std::function<void()>& after_batch) {
  runner::VariantRunner& runner = *devices.first;
  const render::DeviceInfo& device = runner.device();
  const std::string ctx = context(runner, view);
  std::map<int, Twin> twin = twins(runner, view, ctx);
  std::vector<Candidate> todo;
  for (int v : sel_.measured) {
    if (v == sel_.baseline || twin.count(v)) continue;
    Candidate cand = candidate(runner, v, ctx);
    if (!reuse(cand, device, view.name)) todo.push_back(std::move(cand));
  }
  order_for_race(todo, o_.timing, view.name);
  order_by_gbuffer(todo, o_.timing, o_.size);
  Candidate ref = candidate(runner, sel_.baseline, ctx);
  if (todo.empty() && reuse(ref, device, view.name)) {
    add_twin_rows(twin, device, view.name);
    return;
  }
  if (o_.truth.enabled) scorer(view);  // the reference before the timing, which it would disturb, and before threads

  const std::string where = fmt::format("{} {}", device.backend, view.name);
  const int batch_size = std::max(1, o_.timing.batch - 1);
  const int batches = std::max<int>(1, static_cast<int>((todo.size() + batch_size - 1) / batch_size));
  const std::size_t workers = still_devices(runner, batches);
  std::vector<runner::VariantRunner*> runners;
  std::vector<std::unique_ptr<render::PreparedPipeline>> ref_pipelines;  // the baseline's, one per device
  for (std::size_t w = 0; w < workers; ++w) {
    runners.push_back(&devices.at(w, scene_));
    ref_pipelines.push_back(runners.back()->prepare(ref.plan));
  }
  PipelineTiming ref_timing;  // accumulates over batches
  std::vector<EarlierRow> earlier;  // the race: this view's rows of the batches before (Retire::earlier)
  std::vector<BatchRows> done(static_cast<std::size_t>(batches));
  const auto work = [&](std::size_t w, std::size_t b) {
    const std::size_t lo = b * static_cast<std::size_t>(batch_size), hi = std::min(todo.size(), lo + batch_size);
    TimingOptions to{o_.timing.warmup, o_.timing.reps, res_.radius, o_.timing.camera_path, o_.timing.auto_reps, std::nullopt};
    // The race's rule reads the batches before: only with one device (still_devices: stills have no race).
    if (o_.timing.auto_reps && o_.timing.races()) to.retire = retire_rule(ref, todo, lo, hi, view.name, earlier);
    done[b] = run_batch(*runners[w], *ref_pipelines[w], ref, todo, lo, hi, view,
                        fmt::format("{}: batch {}/{}", where, b + 1, batches), to, workers == 1);
    done[b].run.device = static_cast<int>(w);
    if (to.retire) add_earlier_rows(earlier, *to.retire, done[b].timed);
  };
  double ref_first_ms = 0;
  const auto keep = [&](std::size_t b) {
    BatchRows& out = done[b];
    const PipelineTiming& batch_ref = out.timed.pipelines[0];
    if (b == 0) ref_first_ms = batch_ref.first_frame_ms;
    ref_timing.total_ms.insert(ref_timing.total_ms.end(), batch_ref.total_ms.begin(), batch_ref.total_ms.end());
    ref_timing.draw_ms.insert(ref_timing.draw_ms.end(), batch_ref.draw_ms.begin(), batch_ref.draw_ms.end());
    ref_timing.stop = batch_ref.stop;
    const std::string id = batch_id(where, static_cast<int>(b));
    for (MeasureRow& row : out.rows) {
      row.rounds.id = id;
      res_.rows.push_back(std::move(row));
      ++rows_measured_;
      last_measured_ = Clock::now();
    }
    if (b + 1 == done.size()) {  // the baseline's own row, from every round of every batch: device 0's pipeline,
      const auto read_start = Clock::now();  // idle now (it renders batches 0, W, 2W, ..., all kept by now)
      MeasureRow row = new_row(ref, device, view.name);
      row.is_baseline = !sel_.baseline_selected;
      ref_timing.first_frame_ms = ref_first_ms;
      finish_row(row, runner, ref, *ref_pipelines[0], ref_timing, view);
      row.rel_time = row.rel_time_median = 1.0;
      row.rounds.id = table::Rounds::kAll;
      row.rounds.ratios.assign(ref_timing.total_ms.size(), 1.0);
      row.set_reps_reached(ref_timing.stop);
      res_.rows.push_back(std::move(row));
      ++rows_measured_;
      last_measured_ = Clock::now();
      out.run.readback_s += seconds_since(read_start);
    }
    res_.runs.push_back(out.run);
    add_twin_rows(twin, device, view.name);
    if (workers > 1) status(fmt::format("{}: batch {}/{} on {} devices", where, b + 1, batches, workers));
    after_batch();
    out = BatchRows{};  // its images and timings are in the rows now
  };
  util::run_in_order(done.size(), workers, work, keep);
}

Retire BatchMeasurer::retire_rule(const Candidate& reference, const std::vector<Candidate>& todo, std::size_t lo,
                                  std::size_t hi, const std::string& view, const std::vector<EarlierRow>& earlier) const {
  auto known = [&](const Candidate& c) {
    if (!o_.timing.race_errors) return double(NAN);
    auto it = o_.timing.race_errors->find({c.plan.variant, view});
    return it == o_.timing.race_errors->end() ? NAN : it->second;
  };
  Retire r{{known(reference)}, o_.timing.race_margin, o_.timing.race_budget, earlier};
  for (std::size_t i = lo; i < hi; ++i) r.known_error.push_back(known(todo[i]));
  return r;
}

// One batch's frames: the stills only (TimingPlan::still_only), else the warm-up and the timed rounds, with the
// stills the race retires by scored between them when it must (race_scores_stills).
RoundRobinResult BatchMeasurer::render_batch(runner::VariantRunner& runner, const std::vector<render::PreparedPipeline*>& pipelines,
                                             const std::vector<int>& still_frames, const scene::View& view, TimingOptions& to,
                                             const std::string& where, bool report) {
  if (o_.timing.still_only) return render_stills(runner.backend(), pipelines, still_frames, view, to);
  const StillsBeforeWarmUp stills{still_frames, [&] {
                                    if (report) status(fmt::format("{}: scoring {} stills", where, pipelines.size()));
                                    score_unknown_errors(runner, pipelines, view, *to.retire);
                                  }};
  RoundRobinResult timed =
      warm_up(runner.backend(), pipelines, view, to, to.retire && o_.timing.race_scores_stills ? &stills : nullptr);
  time_rounds(runner.backend(), pipelines, view, to, timed, [&](const std::string& s) {
    if (report) status(fmt::format("{}: {} ({} pipelines)", where, s, pipelines.size()));
  });
  return timed;
}

// TimingPlan::race_scores_stills: each pipeline whose still the race does not know the error of yet, read back and
// scored against the view's reference as finish_row scores its row. The reference (pipeline 0) only when it is a
// selected variant: a timing-only baseline is no row of the table, and retires nothing by its error.
void BatchMeasurer::score_unknown_errors(runner::VariantRunner& runner, const std::vector<render::PreparedPipeline*>& pipelines,
                                         const scene::View& view, Retire& rule) {
  const runner::ViewScorer& score = scorer(view);
  for (std::size_t i = sel_.baseline_selected ? 0 : 1; i < pipelines.size() && i < rule.known_error.size(); ++i)
    if (std::isnan(rule.known_error[i])) rule.known_error[i] = score(runner.read(*pipelines[i]).image).rmse;
}

// Variants that run the same code as an earlier one in key order on this device (same_code.h), once this
// backend's first twin pair rendered bit-identical images; none where it did not, or where the device
// honours RelaxedPrecision. The baseline is grouped only when selected (its timing-only row is no table row).
std::map<int, BatchMeasurer::Twin> BatchMeasurer::twins(runner::VariantRunner& runner, const scene::View& view,
                                                        const std::string& ctx) {
  const render::DeviceInfo& device = runner.device();
  auto checked = twins_alike_.find(device.backend);
  if (!device.ignores_relaxed_precision || (checked != twins_alike_.end() && !checked->second)) return {};
  const int t = c_.target_index(runner.target());
  std::vector<std::string> identities;
  for (int v : sel_.measured)
    identities.push_back(executable_identity(c_, t, runner.plan(v, o_.params, false), compile::relaxed_precision_only()));
  std::map<int, int> groups = group_twins(sel_.measured, identities, sel_.baseline);
  if (groups.empty()) return {};
  if (checked == twins_alike_.end()) {
    const auto& [twin, rep] = *groups.begin();
    const bool alike = twins_render_alike(runner, view, rep, twin);
    twins_alike_[device.backend] = alike;
    if (!alike) return {};
  }
  std::map<int, Twin> out;
  for (const auto& [v, rep] : groups) out.emplace(v, Twin{rep, candidate(runner, v, ctx)});
  return out;
}

// The check the sharing rests on, done for real once per backend and run: one frame of a representative and
// of its twin, compared bit for bit. A difference means the device does not run them alike after all.
bool BatchMeasurer::twins_render_alike(runner::VariantRunner& runner, const scene::View& view, int rep, int twin) {
  auto still = [&](int v) {
    render::PipelinePlan plan = runner.plan(v, o_.params, false);
    auto p = runner.prepare(plan);
    return runner.render_still(*p, plan, view, res_.radius).image;
  };
  const std::string& a = c_.space.variants[rep].key, &b = c_.space.variants[twin].key;
  render::DeviceInfo& device = res_.devices.back();  // this backend's (measure_all)
  const bool alike = same_pixels(still(rep), still(twin));
  if (alike) {
    device.precision += fmt::format("; verified: {} and {} render bit-identical images", a, b);
  } else {
    device.ignores_relaxed_precision = false;
    device.precision = fmt::format("mediump twins measured separately: {} and {} render different images", a, b);
    if (progress_)
      progress_(fmt::format("note: {}: {} and {} run the same code but for RelaxedPrecision yet render different "
                            "images: mediump twins are measured separately on {}", device.backend, a, b,
                            device.backend));
  }
  return alike;
}

void BatchMeasurer::add_twin_rows(std::map<int, Twin>& twins, const render::DeviceInfo& device,
                                  const std::string& view) {
  for (auto it = twins.begin(); it != twins.end();) {
    const std::string& rep = c_.space.variants[it->second.representative].key;
    auto row = std::find_if(res_.rows.begin(), res_.rows.end(), [&](const MeasureRow& r) {
      return r.variant == rep && r.backend == device.backend && r.view == view;
    });
    if (row == res_.rows.end()) {
      ++it;
      continue;
    }
    MeasureRow copy = twin_row(*row, new_row(it->second.cand, device, view));
    if (copy.reused) ++res_.reused;
    res_.rows.push_back(std::move(copy));
    it = twins.erase(it);
  }
}

// Flicker along the view's camera path (every variant), and for progressive ones the error of a single frame
// (a plan whose average reads this frame's half twice, prepared for the purpose).
void BatchMeasurer::temporal_errors(MeasureRow& row, runner::VariantRunner& runner, const render::PipelinePlan& plan,
                                    render::PreparedPipeline& p, const scene::View& view) {
  row.flicker = metrics::flicker(runner.render_path(p, view, res_.radius, 0, std::max(2, view.path_frames)));
  if (!plan.progressive) return;
  auto single = runner.prepare(render::plan_single_frame(plan));
  runner.backend().render(*single, {&view, 0, true, res_.radius});
  row.error_one_frame = scorer(view)(runner.read(*single).image);
}

void BatchMeasurer::finish_row(MeasureRow& row, runner::VariantRunner& runner, const Candidate& cand,
                               render::PreparedPipeline& p, const PipelineTiming& timing, const scene::View& view) {
  row.time_ms = util::summarize(timing.total_ms);
  row.set_passes(pass_stats(render::plan_for_size(cand.plan, o_.size), timing));  // the draws that ran
  row.create_ms = p.create_ms;
  row.first_frame_ms = timing.first_frame_ms;
  row.jit_ms = std::max(0.0, timing.first_frame_ms - row.time_ms.min);
  runner::Still still = runner.read(p);
  row.health = still.health;
  row.mean_visibility = still.mean_visibility;
  row.result = std::move(still.image);
  const std::string rel = (fs::path("images") / row.backend / view.name / row.variant).string();
  if (!o_.out.empty() && o_.images) {
    util::check_path_component(view.name, "view name");
    util::check_path_component(row.variant, "variant key");
    image::write_pfm(o_.out / (rel + ".pfm"), row.result);
    image::write_png(o_.out / (rel + ".png"), row.result);
    row.image = rel + ".pfm";
    row.preview = rel + ".png";
  }
  if (o_.truth.enabled) {
    const auto& truth = ground_truth(view);
    row.error = scorer(view)(row.result);  // with where the error comes from
    // A row the race retired is off the front (Retire): its flicker, a view's path_frames more renders (and a
    // pipeline more for a progressive one), would decide nothing.
    if (o_.truth.temporal && timing.stop != Stop::dominated) temporal_errors(row, runner, cand.plan, p, view);
    if (!o_.out.empty() && o_.images) {
      metrics::write_error_heatmap(o_.out / (rel + ".error.png"), row.result, truth.visibility, truth.background);
      row.error_map = rel + ".error.png";
    }
  }
  row.list_images();
}

}  // namespace aovar::measure
