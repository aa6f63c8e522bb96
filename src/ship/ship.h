#pragma once
// `aovar ship` (issue 35; docs/cli.md): from a scene to the variant to ship, in one command.
//   1. profile the scene on all its views: what it prunes from the space, and whether its buffered normals
//      lean from their faces (then the search keeps normals derived from depth and fits with them);
//   2. fit every method's parameters on the scene's training views (calibrate), held-out views apart;
//   3. search the pruned space by racing (race.h): a screen of every candidate, its still error only (no
//      flicker along the camera path, no images) and a few timed repetitions (with a GPU target: one render, no
//      timing, and views in turn: the other training views only for what the first one's error and traced estimate leave, see
//      bounded_estimate.h; when every candidate fits one batch of the race: no screen, the race scores the stills itself),
//      the dominated ones eliminated with their reason, then the survivors
//      with every measure of a sweep, timed until their intervals are narrow (--reps auto), except that a
//      candidate a more accurate one of its batch or an earlier batch already beats beyond the margin stops
//      being timed on that view (measure::Retire; the screen's front is timed first), eliminated again.
//      On a measured backend the held-out views then render the survivors' stills and time only those the
//      query could choose (holdout.h);
//   4. select among the survivors on the held-out views, write the cost table and the reports, and say what
//      to ship with the line that generates exactly that variant.
// Resumable: every round is a sweep into OUT/<round> (rows reused after a kill), the profile and the
// calibration are read back while their inputs are unchanged (OUT/ship.json records what they were fitted on).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "decide/select.h"
#include "measure/timing.h"
#include "compile/run_scope.h"
#include "shard/env.h"
#include "render/backend.h"
#include "render/frame.h"
#include "ship/holdout.h"
#include "ship/race.h"
#include "table/table.h"

namespace aovar::ship {

struct ShipOptions {
  compile::RunScope scope;                 // the manifest, rendering threads, jobs, the cache root
  std::string scene = "builtin:atrium";
  std::filesystem::path views_file;
  std::vector<std::string> holdout_views;  // empty: calibrate::split_views' default (every third view)
  std::vector<std::string> globs;          // the space searched (empty: every variant of the manifest)
  // GPUs with an estimate (AMD families, GL chips): time is each one's traced estimate (no timing rounds).
  // Several: one search (one profile, fit and screen of errors), a choice per GPU. Empty: measured on `backend`.
  std::vector<std::string> targets;
  std::string backend = render::default_backend();        // the measured backend (and, with targets, the one tracing)
  decide::SelectQuery query;                // budget_of, budget_ms or max_error; ship sets the filters
  render::Extent size{640, 360};
  render::Extent fit_size{320, 180};       // calibration renders (calibrate's default)
  int fit_evaluations = 40;                // per method
  // Pipelines prepared and timed together on a measured backend; 0: batch_for(size). Larger than a sweep's 24
  // where the frame allows: a candidate retires against its batch in shared rounds, the sharpest comparison.
  int batch = 0;
  int race_reps = 6;                       // the first round: the fewest rounds whose sign-test interval is known
  double race_margin = 1.10;               // measured backends: eliminate on a slowdown whose interval is above it (race.h)
  measure::AutoReps final_reps;            // the second round: --reps auto with this target and cap
  int rays = 256;
  render::Extent gpu_frame{1920, 1080};
  double gpu_window = 0.5;
  std::filesystem::path out;
  // Sharded (shards.h): a sharded run profiles, fits and screens its share, then stops; `join` (the shards'
  // folders) takes their fit and merged screens and carries on from there.
  shard::ShardSpec shard;
  std::vector<std::filesystem::path> join;
};

struct Round {
  std::string name;      // "screen", then "race" (measured backend) or "front" (GPU target)
  std::string timing;    // "6 reps", "--reps auto ...", "one render, estimate on navi21"
  int candidates = 0, eliminated = 0;
  double seconds = 0;
};

// What to ship on one target: a GPU of --target, or the measured backend (target empty).
struct ShipChoice {
  std::string target;
  // The variants that survived the search on this target (several targets: each has its own eliminations;
  // the table holds the union). The choice is made among them on the held-out views.
  std::vector<std::string> survivors;
  decide::Selection selection;
};

struct ShipResult {
  std::vector<std::string> training, holdout;  // views
  bool lean = false;                           // buffered normals lean on some view
  std::string lean_text;                       // the evidence, per view
  std::string fit_normals;                     // "depth" or "buffer"
  int selected = 0, pruned = 0, lean_dropped = 0;  // variants the globs select; dropped by the profile; by the lean
  std::vector<Round> rounds;
  std::vector<std::pair<std::string, Elimination>> eliminated;  // round name, what and why
  table::CostTable table;                      // the last round's rows, meta.ship: every choice made
  std::string holdout_rule;                    // which survivors the held-out views timed (holdout.h)
  std::vector<HoldoutSkip> holdout_untimed;    // the survivors they did not, each with its held-out rmse
  int holdout_timed = 0;
  std::vector<ShipChoice> choices;             // one per target, in --target order; one for a measured backend
  // `aovar generate` of exactly the chosen variant; for several GPUs, of one library whose pick() serves each
  // GPU its choice (--from-table this table --for the targets, with the query).
  std::string build_line;
  std::string shard;                           // "2/4" when this run was one shard: its screen only, no selection
  std::string shard_balance;                   // a shard: its share of the plan; a join: the shards' balance
  double wall_s = 0;
};

using Progress = std::function<void(const std::string&)>;

// The default --batch: 128 pipelines at 640x360 or less, fewer for larger frames (each prepared pipeline holds
// its frame's render targets), never under a sweep's 24.
int batch_for(render::Extent size);

// Throws std::runtime_error with one line (scene, view, manifest, query and backend errors; an empty search).
ShipResult run_ship(const ShipOptions& options, const Progress& progress = {});

// What `aovar ship` prints: the choices made, the rounds, what to ship with its held-out numbers, the line.
std::string to_text(const ShipResult& result, const ShipOptions& options);

}  // namespace aovar::ship
