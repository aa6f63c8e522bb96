#include "measure/measure.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <fmt/format.h>
#include <malloc.h>
#include <nlohmann/json.hpp>

#include "compile/generate.h"
#include "image/contact_sheet.h"
#include "measure/scene_prune.h"
#include "shadergen/expand.h"
#include "util/fs.h"
#include "util/glob.h"
#include "util/hash.h"

namespace aovar::measure {
namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

variants::Target backend_target(const std::string& backend) {
  if (backend == "lavapipe") return variants::Target::vulkan;
  if (backend == "osmesa") return variants::Target::gl45;
  throw render::BackendError(fmt::format("unknown backend '{}' (use lavapipe or osmesa)", backend));
}

std::string size_text(render::Extent e) { return fmt::format("{}x{}", e.width, e.height); }

json stats_json(const TimeStats& s) {
  return {{"min", s.min}, {"median", s.median}, {"p90", s.p90}, {"n", s.n}};
}
TimeStats stats_from(const json& j) {
  return {j.at("min").get<double>(), j.at("median").get<double>(), j.at("p90").get<double>(), j.at("n").get<int>()};
}

// DESIGN.md §6 `error`; PSNR of identical images is +inf, which JSON cannot hold: written as null.
json error_json(const metrics::ErrorStats& e) {
  return {{"rmse", e.rmse}, {"mae", e.mae}, {"psnr", std::isfinite(e.psnr) ? json(e.psnr) : json(nullptr)},
          {"ssim", e.ssim}, {"bias", e.bias}, {"max", e.max}, {"share_over_0_1", e.share_over_0_1},
          {"pixels", e.health.pixels}};
}
metrics::ErrorStats error_from(const json& j) {
  metrics::ErrorStats e;
  e.rmse = j.at("rmse");
  e.mae = j.at("mae");
  e.psnr = j.at("psnr").is_null() ? std::numeric_limits<double>::infinity() : j.at("psnr").get<double>();
  e.ssim = j.at("ssim");
  e.bias = j.at("bias");
  e.max = j.at("max");
  e.share_over_0_1 = j.at("share_over_0_1");
  e.health.pixels = j.at("pixels");
  return e;
}

json row_json(const MeasureRow& r, const MeasureResult& res, const MeasureOptions& o) {
  json axes = json::object();
  for (const auto& [k, v] : r.axes) axes[k] = v;
  json passes = json::object();
  for (const auto& [k, s] : r.passes) passes[k] = stats_json(s);
  return {{"variant", r.variant}, {"axes", axes}, {"duplicates", r.duplicates}, {"scene", res.scene},
          {"view", r.view}, {"backend", r.backend}, {"size", size_text(o.size)}, {"threads", o.threads},
          {"radius", res.radius}, {"spirv_hash", r.spirv_hash}, {"inputs_hash", r.inputs_hash},
          {"time_ms", stats_json(r.time)}, {"passes", passes}, {"rel_time", r.rel_time},
          {"rel_time_median", r.rel_time_median}, {"baseline", r.baseline}, {"is_baseline", r.is_baseline},
          {"create_ms", r.create_ms}, {"first_frame_ms", r.first_frame_ms}, {"jit_ms", r.jit_ms},
          {"health", {{"nan", r.health.nan}, {"inf", r.health.inf}, {"out_of_range", r.health.out_of_range},
                      {"pixels", r.health.pixels}}},
          {"mean_visibility", r.mean_visibility}, {"error", r.error ? error_json(*r.error) : json(nullptr)},
          {"error_one_frame", r.error_one_frame ? error_json(*r.error_one_frame) : json(nullptr)},
          {"flicker", r.flicker ? json(*r.flicker) : json(nullptr)},
          {"image", r.image}, {"preview", r.preview}, {"error_map", r.error_map}};
}

MeasureRow row_from(const json& j) {
  MeasureRow r;
  r.variant = j.at("variant");
  for (auto& [k, v] : j.at("axes").items()) r.axes.emplace_back(k, v.get<std::string>());
  r.duplicates = j.at("duplicates").get<std::vector<std::string>>();
  r.backend = j.at("backend");
  r.view = j.at("view");
  r.spirv_hash = j.at("spirv_hash");
  r.inputs_hash = j.at("inputs_hash");
  r.time = stats_from(j.at("time_ms"));
  for (auto& [k, v] : j.at("passes").items()) r.passes.emplace_back(k, stats_from(v));
  r.rel_time = j.at("rel_time");
  r.rel_time_median = j.at("rel_time_median");
  r.baseline = j.at("baseline");
  r.is_baseline = j.at("is_baseline");
  r.create_ms = j.at("create_ms");
  r.first_frame_ms = j.at("first_frame_ms");
  r.jit_ms = j.at("jit_ms");
  const json& h = j.at("health");
  r.health = {h.at("nan"), h.at("inf"), h.at("out_of_range"), h.at("pixels")};
  r.mean_visibility = j.at("mean_visibility");
  if (!j.at("error").is_null()) r.error = error_from(j.at("error"));
  if (!j.at("error_one_frame").is_null()) r.error_one_frame = error_from(j.at("error_one_frame"));
  if (!j.at("flicker").is_null()) r.flicker = j.at("flicker").get<double>();
  r.image = j.at("image");
  r.preview = j.at("preview");
  r.error_map = j.at("error_map");
  r.reused = true;
  return r;
}

// An earlier measure.json: its rows and kept rows by inputs hash, with their JSON (a missing or unreadable
// file reuses nothing), and its contact sheets with the rows they show.
struct Previous {
  std::map<std::string, MeasureRow> rows;
  std::map<std::string, json> text;
  std::vector<std::string> contact_sheets;
  std::string contact_sheets_rows;
};
Previous previous_rows(const fs::path& out, bool need_images, const Progress& say) {
  Previous prev;
  auto text = util::read_file(out / "measure.json");
  if (!text) return prev;
  try {
    json doc = json::parse(*text);
    for (const char* list : {"rows", "kept_rows"})
      for (const auto& j : doc.value(list, json::array())) {
        MeasureRow r = row_from(j);
        // Measured without images, or its image went missing: measure again.
        if (r.image.empty() ? need_images : !fs::exists(out / r.image)) continue;
        prev.text.emplace(r.inputs_hash, j);
        prev.rows.emplace(r.inputs_hash, std::move(r));
      }
    prev.contact_sheets = doc.value("contact_sheets", std::vector<std::string>{});
    prev.contact_sheets_rows = doc.value("contact_sheets_rows", "");
  } catch (const std::exception& e) {
    prev = {};  // an older or damaged file: measure everything again
    if (say) say(fmt::format("note: {}: not reused ({}); measuring everything again",
                             util::display_path(out / "measure.json"), e.what()));
  }
  return prev;
}

// Which rows a set of contact sheets shows: their inputs, in order.
std::string rows_fingerprint(const std::vector<MeasureRow>& rows) {
  util::Hasher h;
  for (const auto& r : rows) h.add(r.inputs_hash);
  return h.hex();
}

struct VariantInputs {
  std::string spirv_hash, inputs_hash;
};

// Everything of a plan the backends execute: the programs (by key; their code is in spirv_hash), the
// resolution and progressive flags, every texture (format, extent, buffering, clears, MIP levels) and every
// draw (programs, parameter block, inputs, outputs, viewport). Variants that differ only in the renderer's
// side (x2 and x4 run the same programs into smaller textures) must not share a row.
std::string plan_text(const render::PipelinePlan& plan) {
  std::string s = fmt::format("res {} prog {} result {}", plan.resolution, plan.progressive, plan.result);
  for (const auto& sh : plan.shaders) s += fmt::format("|shader {} {}", sh.program_key, variants::stage_name(sh.stage));
  for (const auto& t : plan.textures)
    s += fmt::format("|tex {} {} {} {} {} {} {}", t.name, render::format_name(t.format), t.full_resolution,
                     t.double_buffered, t.cleared, fmt::join(t.clear, ","), t.levels);
  for (const auto& b : plan.depth_buffers) s += fmt::format("|zbuf {} {}", b.name, b.full_resolution);
  auto ref = [](const render::TextureRef& r) { return fmt::format("{}/{}/{}", r.texture, r.previous, r.level); };
  for (const auto& d : plan.draws) {
    s += fmt::format("|draw {} {} {} {} {} {} {} [{}] depth {} {}", d.name, d.pass, d.geometry, d.vertex, d.fragment,
                     d.full_resolution, d.level, fmt::join(d.params, ","), render::depth_use_name(d.depth),
                     d.depth_buffer);
    for (const auto& [binding, in] : d.inputs) s += fmt::format(" in{}={}", binding, ref(in));
    for (const auto& out : d.outputs) s += " out=" + ref(out);
  }
  return s;
}

VariantInputs variant_inputs(const compile::CompiledSpace& c, int v, int t, const render::PipelinePlan& plan,
                             const std::string& context) {
  util::Hasher programs;
  for (const auto& pass : c.space.variants[v].passes)
    for (int p : pass)
      if (p >= 0) programs.add(c.builds[t][p].hash);
  VariantInputs in;
  in.spirv_hash = programs.hex();
  // The key too: identical variants are measured once per run anyway (duplicates), and a row never
  // stands in for another variant whatever the plan text leaves out.
  util::Hasher all;
  all.add(in.spirv_hash).add(context).add(c.space.variants[v].key).add(plan_text(plan));
  in.inputs_hash = all.hex();
  return in;
}

std::string view_text(const scene::View& v) {
  return fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}", v.name, v.eye.x, v.eye.y, v.eye.z,
                     v.target.x, v.target.y, v.target.z, v.up.x, v.up.y, v.up.z, v.fov_y_deg, v.near_plane,
                     v.far_plane, v.path_offset.x, v.path_offset.y, v.path_offset.z, v.path_frames);
}

void write_json(const MeasureResult& res, const MeasureOptions& o) {
  if (o.out.empty()) return;
  util::write_atomic(o.out / "measure.json", to_json(res, o).dump(1) + "\n");
}

struct Candidate {
  int variant;
  render::PipelinePlan plan;
  VariantInputs inputs;
};

}  // namespace

void keep_heap_mapped() {
  // llvmpipe allocates and frees large vertex-setup buffers on every geometry draw. With glibc's default
  // thresholds those come from fresh mmaps or are trimmed back to the OS each time, so each frame pays
  // page faults again and G-buffer times jump 2-4x at random (atrium: 5.3 ms alone, 13-20 ms between AO
  // passes). Keeping freed memory in the heap removes that noise from every backend alike.
  static const bool once = [] {
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    return true;
  }();
  (void)once;
}

MeasureRow::Health image_health(const image::FloatImage& img) {
  MeasureRow::Health h;
  h.pixels = static_cast<long>(img.pixels.size());
  for (float v : img.pixels) {
    if (std::isnan(v)) ++h.nan;
    else if (std::isinf(v)) ++h.inf;
    else if (v < 0.0f || v > 1.0f) ++h.out_of_range;
  }
  return h;
}

// One labelled contact sheet per backend and view (rows sorted by variant, so methods sit together), from
// the PFM files on disk: reused rows have no image in memory.
static std::vector<std::string> write_contact_sheets(const MeasureResult& res, const fs::path& out) {
  std::vector<std::string> written;
  for (std::size_t lo = 0; lo < res.rows.size();) {
    std::size_t hi = lo;
    std::vector<image::SheetTile> tiles;
    // With --reference, the ray-traced reference of the view leads the sheet.
    if (fs::path truth = out / "images" / "reference" / (res.rows[lo].view + ".pfm"); fs::exists(truth)) {
      auto img = image::read_pfm(truth);
      double sum = 0;
      for (float v : img.pixels) sum += v;
      tiles.push_back({fmt::format("ray-traced reference\nmean {:.3f}", img.pixels.empty() ? 0.0 : sum / img.pixels.size()),
                       std::move(img)});
    }
    while (hi < res.rows.size() && res.rows[hi].backend == res.rows[lo].backend &&
           res.rows[hi].view == res.rows[lo].view) {
      const MeasureRow& r = res.rows[hi++];
      if (r.image.empty() || !fs::exists(out / r.image)) continue;
      tiles.push_back({fmt::format("{}\nmean {:.3f}  {:.2f} ms{}", r.variant, r.mean_visibility, r.time.min,
                                   r.is_baseline ? "  (baseline)" : ""),
                       image::read_pfm(out / r.image)});
    }
    if (tiles.size() >= 2) {  // (a reference and one variant make a sheet too)
      int columns = std::max(1, static_cast<int>(std::lround(std::sqrt(2.0 * tiles.size()))));
      std::string rel = fmt::format("contact_sheet-{}-{}.png", res.rows[lo].backend, res.rows[lo].view);
      image::write_png(out / rel, image::contact_sheet(tiles, columns, 320));
      written.push_back(rel);
    }
    lo = hi;
  }
  return written;
}

int shard_of(const std::string& key, int shard_count) {
  if (shard_count <= 1) return 0;
  util::Hasher h;
  h.add(key);
  return static_cast<int>(std::stoull(h.hex().substr(0, 12), nullptr, 16) % static_cast<unsigned long long>(shard_count));
}

MeasureResult run_measure(const MeasureOptions& o, const Progress& progress) {
  keep_heap_mapped();
  auto start = Clock::now();
  auto say = [&](const std::string& s) { if (progress) progress(s); };
  if (o.reps < 1) throw std::runtime_error("--reps must be at least 1");
  if (o.size.width < 1 || o.size.height < 1) throw std::runtime_error("--size must be WxH with W, H >= 1");
  if (o.shard_count < 1 || o.shard_index < 0 || o.shard_index >= o.shard_count)
    throw std::runtime_error(fmt::format("--shard {}/{}: use k/n with 1 <= k <= n", o.shard_index + 1, o.shard_count));
  MeasureResult res;

  scene::LoadOptions load;
  load.views_file = o.views_file;
  scene::Scene sc = scene::load_scene(o.scene, load);
  std::vector<const scene::View*> views;
  if (o.views.empty()) views.push_back(&sc.views.front());
  for (const auto& name : o.views)  // each view once, in the order given
    if (std::none_of(views.begin(), views.end(), [&](const scene::View* v) { return v->name == name; }))
      views.push_back(&sc.view(name));
  res.scene = sc.name;
  res.scene_hash = sc.content_hash;
  res.triangles = sc.triangle_count();
  res.radius = o.radius > 0 ? o.radius : sc.ao_radius;

  // Compile what the backends need (the baseline variant too, when globs would leave it out).
  std::vector<variants::Target> targets;
  for (const auto& b : o.backends) {
    auto t = backend_target(b);
    if (std::find(targets.begin(), targets.end(), t) == targets.end()) targets.push_back(t);
  }
  compile::CompileOptions co;
  co.targets = targets;
  co.globs = o.globs;
  if (!co.globs.empty()) co.globs.push_back(o.baseline);
  co.cache_dir = o.cache_dir;
  co.jobs = o.jobs;

  // What the scene's profile drops is not compiled (the baseline, the pairing reference, is timed anyway).
  if (o.prune_by_profile || o.pruning) {
    res.pruning = o.pruning ? o.pruning : std::make_shared<const ScenePruning>(prune_scene(o, sc, views, o.globs, progress));
    const ScenePruning& pr = *res.pruning;
    say(pr.summary(o.globs) + (pr.reused ? " (profile reused)" : fmt::format(" (profiled in {:.1f} s)", pr.seconds)));
    bool dropped = false;
    for (const auto& d : pr.dropped)
      if (util::glob_any(o.globs, d.variant)) {
        dropped = true;
        if (d.variant != o.baseline) co.exclude.insert(d.variant);
      }
    if (dropped && std::none_of(pr.kept.begin(), pr.kept.end(), [&](const std::string& k) { return util::glob_any(o.globs, k); })) {
      // Nothing left to measure: the log of what was dropped, and the earlier rows kept for later runs.
      say(fmt::format("note: scene {} drops every selected variant: nothing to measure (--no-prune measures them)", o.scene));
      res.counts = "every selected variant dropped by the scene's profile";
      res.kept_rows = json::array();
      if (o.reuse && !o.out.empty())
        for (const auto& [hash, j] : previous_rows(o.out, false, progress).text) res.kept_rows.push_back(j);
      res.wall_s = seconds_since(start);
      write_json(res, o);
      return res;
    }
  }
  auto compile_start = Clock::now();
  compile::CompiledSpace c = compile::compile_space(o.manifest, co);
  res.compile_s = seconds_since(compile_start);
  if (!c.ok())
    throw std::runtime_error(fmt::format("{} (and {} more diagnostics): fix the templates first (aovar generate shows all)",
                                         c.diagnostics.empty() ? "compile failed" : c.diagnostics.front(),
                                         c.diagnostics.empty() ? 0 : c.diagnostics.size() - 1));

  // Selection: globs, then variant dedup. The first selected variant of each group of identical variants
  // is measured; the other selected ones are listed as its duplicates.
  std::vector<int> selected;
  std::map<int, int> representative;  // canonical variant -> the selected variant measured for its group
  std::map<int, std::vector<std::string>> duplicates;  // by representative
  auto canonical = [&](int v) { return c.variant_same_as[v] >= 0 ? c.variant_same_as[v] : v; };
  int baseline = -1;
  for (int v = 0; v < static_cast<int>(c.space.variants.size()); ++v) {
    const std::string& key = c.space.variants[v].key;
    if (key == o.baseline) baseline = v;
    if (!util::glob_any(o.globs, key) || o.skip.count(key) || (res.pruning && res.pruning->drops(key))) continue;
    if (o.shard_count > 1 && shard_of(key, o.shard_count) != o.shard_index) continue;
    auto [it, fresh] = representative.emplace(canonical(v), v);
    if (fresh) selected.push_back(v);
    else duplicates[it->second].push_back(key);
  }
  if (selected.empty() && o.shard_count > 1) {
    say(fmt::format("note: shard {}/{} holds none of the selected variants", o.shard_index + 1, o.shard_count));
    return res;
  }
  if (selected.empty())
    throw std::runtime_error(fmt::format("{}: no variant matches --variants {} (aovar list shows the keys)",
                                         c.manifest.error_prefix(), fmt::join(o.globs, " ")));
  if (baseline < 0) {
    baseline = selected.front();
    say(fmt::format("note: baseline {} is not in the manifest; using {}", o.baseline, c.space.variants[baseline].key));
  } else if (auto it = representative.find(canonical(baseline)); it != representative.end()) {
    baseline = it->second;  // identical to a selected variant: that one's row is the baseline row
  }
  bool baseline_selected = std::find(selected.begin(), selected.end(), baseline) != selected.end();
  if (res.pruning && res.pruning->drops(c.space.variants[baseline].key))
    say(fmt::format("note: the baseline {} is dropped by the scene's profile: timed as the pairing reference only",
                    c.space.variants[baseline].key));
  // --param: each override must be a parameter of at least one selected variant (variants without it,
  // e.g. blur.radius_px on an unblurred one, simply do not take it).
  std::set<std::string> parameters;
  for (int v : selected)
    for (auto& key : render::parameter_keys(c, v)) parameters.insert(std::move(key));
  for (const auto& [key, value] : o.params)
    if (!parameters.count(key))
      throw std::runtime_error(fmt::format("--param {}: no selected variant has this parameter (they have: {})", key,
                                           fmt::join(parameters, ", ")));
  res.counts = compile::counts_line(c);

  // Progress: rows done out of rows wanted, and an ETA from the time per measured (not reused) row.
  const std::size_t rows_wanted = (selected.size() + (baseline_selected ? 0 : 1)) * views.size() * o.backends.size();
  std::size_t rows_measured = 0;
  auto measuring_start = Clock::now();
  auto status = [&](const std::string& what) {
    std::string eta;
    std::size_t done = res.rows.size();
    if (rows_measured > 0 && done < rows_wanted) {
      double per_row = seconds_since(measuring_start) / static_cast<double>(rows_measured);
      auto left = static_cast<long>(per_row * static_cast<double>(rows_wanted - done));
      eta = fmt::format(", ETA {}m{:02}s", left / 60, left % 60);
    }
    say(fmt::format("[{}/{} rows{}] {}", done, rows_wanted, eta, what));
  };

  Previous earlier = o.reuse && !o.out.empty() ? previous_rows(o.out, o.images, progress) : Previous{};
  const auto& previous = earlier.rows;
  // Earlier rows this run does not produce stay reusable (a narrower sweep, the first phase of a pruned one),
  // unless this run writes their image (same backend, view and variant: a row with other inputs).
  {
    std::set<std::string> produced;
    for (int v : selected) produced.insert(c.space.variants[v].key);
    produced.insert(c.space.variants[baseline].key);
    res.kept_rows = json::array();
    for (const auto& [hash, r] : previous)
      if (!produced.count(r.variant) ||
          std::find(o.backends.begin(), o.backends.end(), r.backend) == o.backends.end() ||
          std::none_of(views.begin(), views.end(), [&](const scene::View* v) { return v->name == r.view; }))
        res.kept_rows.push_back(earlier.text.at(hash));
  }

  // Ground truth: one ray-traced reference per view, at the measured size, radius and camera pose (the last
  // frame of the path with --camera-path, as the images are), shared by every backend and variant. Its
  // cache key (scene, camera, size, radius, rays, mode) is part of every row's inputs; the image itself is
  // traced (or loaded from the cache) only for a view with rows to measure, or whose copy under
  // images/reference/ is missing, so a repeated run traces nothing.
  auto reference_options = [&] {
    reference::ReferenceOptions ro;
    ro.size = o.size;
    ro.radius = res.radius;
    ro.rays = o.reference_rays;
    ro.mode = o.reference_mode;
    ro.frame = o.camera_path ? o.warmup + o.reps : 0;
    ro.cache_dir = o.reference_cache;
    return ro;
  };
  std::map<std::string, reference::ReferenceImage> truth;
  auto ground_truth = [&](const scene::View& view) -> const reference::ReferenceImage& {
    if (auto it = truth.find(view.name); it != truth.end()) return it->second;
    auto ref = reference::trace_reference(sc, view, reference_options(), [&](double f, double elapsed) {
      say(fmt::format("reference {}: {:.0f} %{}", view.name, 100 * f,
                      f > 0.01 ? fmt::format(", ETA {:.0f} s", elapsed * (1 - f) / f) : std::string()));
    });
    if (!o.out.empty() && o.images) reference::write_reference(o.out / "images" / "reference" / view.name, ref);
    return truth.emplace(view.name, std::move(ref)).first->second;
  };

  for (const auto& backend_name : o.backends) {
    variants::Target target = backend_target(backend_name);
    int t = c.target_index(target);
    render::BackendOptions bo;
    bo.threads = o.threads;
    auto backend = render::make_backend(backend_name, bo);
    res.devices.push_back(backend->info());
    backend->set_scene(sc);

    for (const scene::View* view : views) {
      // Every input of a row but the variant's own (programs, key, plan: variant_inputs). The selection and
      // --batch are not inputs: the paired time (ratio to the baseline in the same rounds) cancels the drift
      // between runs, so rows measured in different runs, or a sweep's pruning phases, combine.
      const auto& info = backend->info();
      std::string context = fmt::format("{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", shadergen::generator_version(),
                                        sc.content_hash, view_text(*view), backend_name, info.device, info.driver,
                                        info.mediump_fp16, size_text(o.size), o.threads, o.reps, o.warmup,
                                        res.radius, c.space.variants[baseline].key);
      if (o.camera_path) context += "|path";
      if (o.ground_truth) context += "|truth:" + reference::cache_key(sc, *view, reference_options());
      auto make = [&](int v) {
        // Calibrated values of the variant's algorithm, then --param on top.
        render::ParamOverrides overrides = o.params;
        auto cal = o.calibration.find(c.manifest.value(variants::Axis::algorithm,
                                                       c.space.variants[v].point[variants::index(variants::Axis::algorithm)]).text);
        if (cal != o.calibration.end()) overrides.insert(cal->second.begin(), cal->second.end());
        Candidate cand{v, render::plan_pipeline(c, v, target, overrides, false), {}};
        cand.inputs = variant_inputs(c, v, t, cand.plan, context);
        return cand;
      };
      auto new_row = [&](const Candidate& cand) {
        MeasureRow row;
        row.variant = cand.plan.variant;
        for (const auto& [k, v] : cand.plan.axes) row.axes.emplace_back(k, v);
        if (auto d = duplicates.find(cand.variant); d != duplicates.end()) row.duplicates = d->second;
        row.backend = backend_name;
        row.view = view->name;
        row.spirv_hash = cand.inputs.spirv_hash;
        row.inputs_hash = cand.inputs.inputs_hash;
        row.baseline = c.space.variants[baseline].key;
        return row;
      };

      // Reuse rows whose inputs are unchanged; everything else is measured in batches with the baseline.
      // What belongs to this run rather than to the measurement (another selection lists other duplicates,
      // and the baseline's row is timing-only when no glob selects it) is taken from this run.
      auto reuse = [&](const Candidate& cand) {
        auto it = previous.find(cand.inputs.inputs_hash);
        if (it == previous.end()) return false;
        MeasureRow row = it->second;
        row.duplicates = new_row(cand).duplicates;
        row.is_baseline = cand.variant == baseline && !baseline_selected;
        res.rows.push_back(std::move(row));
        ++res.reused;
        return true;
      };
      std::vector<Candidate> todo;
      for (int v : selected) {
        if (v == baseline) continue;
        Candidate cand = make(v);
        if (!reuse(cand)) todo.push_back(std::move(cand));
      }
      // The baseline is re-measured whenever anything else is (rel_time needs it in the same rounds).
      Candidate ref = make(baseline);
      if (todo.empty() && reuse(ref)) continue;
      if (o.ground_truth) ground_truth(*view);  // before the timing, which it would disturb

      std::string where = fmt::format("{} {}", backend_name, view->name);
      auto prep_start = Clock::now();
      auto ref_pipeline = backend->prepare(ref.plan, o.size);
      PipelineTiming ref_timing;  // accumulates over batches
      double ref_first_ms = 0;
      int batch_size = std::max(1, o.batch - 1);
      int batches = std::max<int>(1, static_cast<int>((todo.size() + batch_size - 1) / batch_size));
      for (int b = 0; b < batches; ++b) {
        std::size_t lo = static_cast<std::size_t>(b) * batch_size;
        std::size_t hi = std::min(todo.size(), lo + batch_size);
        RunRecord run{backend_name, view->name, static_cast<int>(hi - lo) + 1};
        std::vector<std::unique_ptr<render::PreparedPipeline>> prepared;
        std::vector<render::PreparedPipeline*> pointers{ref_pipeline.get()};
        for (std::size_t i = lo; i < hi; ++i) {
          status(fmt::format("{}: batch {}/{}: preparing {}", where, b + 1, batches, todo[i].plan.variant));
          prepared.push_back(backend->prepare(todo[i].plan, o.size));
          pointers.push_back(prepared.back().get());
        }
        run.prepare_s = seconds_since(prep_start);

        TimingOptions to{o.warmup, o.reps, res.radius, o.camera_path};
        auto timed = time_round_robin(*backend, pointers, *view, to, [&](const std::string& s) {
          status(fmt::format("{}: batch {}/{}: {} ({} pipelines)", where, b + 1, batches, s, pointers.size()));
        });
        run.warmup_s = timed.wall_warmup_s;
        run.timed_wall_s = timed.wall_timed_s;
        run.timed_sum_s = timed.sum_timed_s;
        const PipelineTiming& batch_ref = timed.pipelines[0];
        if (b == 0) ref_first_ms = batch_ref.first_frame_ms;
        double ref_min = summarize(batch_ref.total_ms).min;
        for (std::size_t k = 0; k < batch_ref.total_ms.size(); ++k) {
          ref_timing.total_ms.push_back(batch_ref.total_ms[k]);
          ref_timing.draw_ms.push_back(batch_ref.draw_ms[k]);
        }

        auto read_start = Clock::now();
        // Flicker along the view's camera path (every variant), and for progressive ones the error of a
        // single frame (a plan whose average reads this frame's half twice, prepared for the purpose).
        auto temporal_errors = [&](MeasureRow& row, const render::PipelinePlan& plan, render::PreparedPipeline& p,
                                   const scene::View& v, const reference::ReferenceImage& ref) {
          render::FrameSetup fs_path;
          fs_path.view = &v;
          fs_path.radius = res.radius;
          std::vector<image::FloatImage> frames;
          for (int f = 0; f < std::max(2, v.path_frames); ++f) {
            fs_path.frame = f;
            backend->render(p, fs_path);
            frames.push_back(backend->read_result(p));
          }
          row.flicker = metrics::flicker(frames);
          if (plan.progressive) {
            auto single = backend->prepare(render::plan_single_frame(plan), o.size);
            render::FrameSetup fs_static;
            fs_static.view = &v;
            fs_static.static_camera = true;
            fs_static.radius = res.radius;
            backend->render(*single, fs_static);
            row.error_one_frame = metrics::compare(backend->read_result(*single), ref.visibility, ref.background);
          }
        };
        auto finish = [&](MeasureRow& row, const Candidate& cand, render::PreparedPipeline& p,
                          const PipelineTiming& timing) {
          row.time = summarize(timing.total_ms);
          row.passes = pass_stats(render::plan_for_size(cand.plan, o.size), timing);  // the draws that ran
          row.create_ms = p.create_ms;
          row.first_frame_ms = timing.first_frame_ms;
          row.jit_ms = std::max(0.0, timing.first_frame_ms - row.time.min);
          row.result = backend->read_result(p);
          row.health = image_health(row.result);
          double sum = 0;
          for (float v : row.result.pixels) sum += std::isfinite(v) ? v : 0.0f;
          row.mean_visibility = row.result.pixels.empty() ? 0 : sum / row.result.pixels.size();
          fs::path rel = fs::path("images") / backend_name / view->name / row.variant;
          if (!o.out.empty() && o.images) {
            image::write_pfm(o.out / (rel.string() + ".pfm"), row.result);
            image::write_png(o.out / (rel.string() + ".png"), row.result);
            row.image = rel.string() + ".pfm";
            row.preview = rel.string() + ".png";
          }
          if (o.ground_truth) {
            const auto& ref = ground_truth(*view);
            row.error = metrics::compare(row.result, ref.visibility, ref.background);
            temporal_errors(row, cand.plan, p, *view, ref);
            if (!o.out.empty() && o.images) {
              metrics::write_error_heatmap(o.out / (rel.string() + ".error.png"), row.result, ref.visibility,
                                           ref.background);
              row.error_map = rel.string() + ".error.png";
            }
          }
        };
        for (std::size_t i = lo; i < hi; ++i) {
          const PipelineTiming& timing = timed.pipelines[i - lo + 1];
          MeasureRow row = new_row(todo[i]);
          finish(row, todo[i], *prepared[i - lo], timing);
          row.rel_time = ref_min > 0 ? row.time.min / ref_min : 0;
          row.rel_time_median = median_ratio(timing, batch_ref);
          res.rows.push_back(std::move(row));
          ++rows_measured;
        }
        if (b == batches - 1) {  // the baseline's own row, from every round of every batch
          MeasureRow row = new_row(ref);
          row.is_baseline = !baseline_selected;
          ref_timing.first_frame_ms = ref_first_ms;
          finish(row, ref, *ref_pipeline, ref_timing);
          row.rel_time = row.rel_time_median = 1.0;
          res.rows.push_back(std::move(row));
          ++rows_measured;
        }
        run.readback_s = seconds_since(read_start);
        res.runs.push_back(run);
        res.wall_s = seconds_since(start);
        write_json(res, o);  // after every batch: an interruption loses at most one batch
        prep_start = Clock::now();
      }
    }
  }
  if (o.ground_truth && o.images && !o.out.empty())  // the contact sheets lead with it
    for (const scene::View* view : views)
      if (!fs::exists(o.out / "images" / "reference" / (view->name + ".pfm"))) ground_truth(*view);
  std::stable_sort(res.rows.begin(), res.rows.end(), [](const MeasureRow& a, const MeasureRow& b) {
    return std::tie(a.backend, a.view, a.variant) < std::tie(b.backend, b.view, b.variant);
  });
  // Composing the sheets reads every image again: not when the sheets on disk already show these rows.
  const std::string shown = rows_fingerprint(res.rows);
  bool current = !earlier.contact_sheets.empty() && earlier.contact_sheets_rows == shown &&
                 std::all_of(earlier.contact_sheets.begin(), earlier.contact_sheets.end(),
                             [&](const std::string& f) { return fs::exists(o.out / f); });
  if (current || !o.contact_sheets) {  // without sheets of its own, a run leaves the earlier ones listed
    res.contact_sheets = earlier.contact_sheets;
    res.contact_sheets_rows = earlier.contact_sheets_rows;
  } else if (!o.out.empty() && o.images) {
    res.contact_sheets = write_contact_sheets(res, o.out);
    res.contact_sheets_rows = shown;
  }
  res.wall_s = seconds_since(start);
  write_json(res, o);
  return res;
}

// The scene profile's pruning: every selected variant it drops with its rule and reason (null: not pruned).
static json pruned_json(const MeasureResult& res, const MeasureOptions& o) {
  if (!res.pruning) return nullptr;
  json j = res.pruning->to_json(o.globs);
  j["profile"] = res.pruning->profile_file;
  j["profile_reused"] = res.pruning->reused;
  j["seconds"] = res.pruning->seconds;
  return j;
}

json to_json(const MeasureResult& res, const MeasureOptions& o) {
  json devices = json::array();
  for (const auto& d : res.devices)
    devices.push_back({{"backend", d.backend}, {"device", d.device}, {"api", d.api_version}, {"driver", d.driver},
                       {"threads", d.threads}});
  json runs = json::array();
  for (const auto& r : res.runs)
    runs.push_back({{"backend", r.backend}, {"view", r.view}, {"pipelines", r.pipelines}, {"prepare_s", r.prepare_s},
                    {"warmup_s", r.warmup_s}, {"timed_wall_s", r.timed_wall_s}, {"timed_sum_s", r.timed_sum_s},
                    {"readback_s", r.readback_s}});
  json rows = json::array();
  for (const auto& r : res.rows) rows.push_back(row_json(r, res, o));
  return {{"tool", "aovar measure"},
          {"scene", {{"name", res.scene}, {"hash", res.scene_hash}, {"triangles", res.triangles}}},
          {"manifest", util::display_path(o.manifest)},
          {"counts", res.counts},
          {"contact_sheets", res.contact_sheets},
          {"contact_sheets_rows", res.contact_sheets_rows},
          {"size", size_text(o.size)},
          {"reps", o.reps},
          {"warmup", o.warmup},
          {"threads", o.threads},
          {"radius", res.radius},
          {"camera_path", o.camera_path},
          {"devices", devices},
          {"runs", runs},
          {"wall_s", res.wall_s},
          {"compile_s", res.compile_s},
          {"reused", res.reused},
          {"rows", rows},
          {"kept_rows", res.kept_rows.is_null() ? json::array() : res.kept_rows},  // null: returned before selecting
          {"pruned", pruned_json(res, o)}};
}

}  // namespace aovar::measure
