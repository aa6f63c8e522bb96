#pragma once
// With a GPU target, ship's screen needs every candidate's traced estimate (trace/row_traffic.h), and tracing
// is its costliest step (about 0.3 s a draw at 1080p on the Vulkan CPU backend). Most candidates do not need it: a candidate
// that a more accurate one beats on the estimate whatever its trace would show is dominated already. The
// estimate of every pass is at least its ALU time (gpu/cache_estimate.h takes the largest of the ALU,
// texture, latency and bandwidth times, then adds the exposed ALU), and the ALU time needs only RADV's
// statistics, not a trace. So the screen estimates in order of error, best first, and a candidate whose ALU
// time alone exceeds the traced estimate of one with strictly less error is eliminated untraced, with that
// evidence; one whose estimate on the first training view already exceeds it is eliminated before its other
// views are traced (the race takes the worst view's estimate, which is at least that one). The rule only ever removes what race.h would remove with the full estimate: it is exact, not a
// prediction. Static costs thereby order the work (issue 35), without the risk of a learned model.
// Views in turn (issue 55): the screen may render every candidate on the first training view only. Its error
// there is a lower bound on its worst, and so is its traced estimate there, so the same rule drops it before its
// other views are rendered; the candidates it cannot drop get them rendered (render_rest), a chunk at a time,
// before those views are traced.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "ship/race.h"
#include "table/table.h"
#include "trace/row_traffic.h"

namespace aovar::ship {

struct BoundedEstimate {
  std::vector<Elimination> eliminated;  // untraced, with their bound and the traced variant that beats it
  int traced = 0;                       // candidates traced
  int first_view_traced = 0;            // candidates traced on the first training view (the traced among them)
  int completed = 0;                    // candidates whose other training views render_rest rendered for this family
  int dropped_early = 0;                // eliminated on the first training view's error, the others never rendered
  trace::RowGpuResult gpu;              // the statistics and the traffic, as the table's meta.gpu
};

// The rows of the training views after the first for `keys` (candidates rendered on the first one only), without
// GPU costs. Called with each chunk that needs them; may return rows rendered for an earlier family.
using RenderRest = std::function<std::vector<table::CostRow>(const std::vector<std::string>& keys)>;

// Adds `request`'s family estimate (one family) to the rows of `screen`: RADV's statistics to every row, the
// traced estimate to the rows on `training` views of each candidate not eliminated, in chunks of `chunk`
// candidates by ascending worst training-view error so far; removes the rows of the eliminated candidates.
// A candidate with rows on fewer than every training view gets the others from `render_rest` (required then)
// once the rule cannot drop it; they join `screen`. `keep` (the budget's variant) is never eliminated. Throws as
// trace::add_gpu_costs.
BoundedEstimate estimate_in_error_order(table::CostTable& screen, const std::vector<std::string>& training,
                                        const trace::RowGpuRequest& request, const std::string& keep,
                                        const std::function<void(const std::string&)>& say, int chunk = 16,
                                        const RenderRest& render_rest = {});

// The estimate no trace can bring below: the sum of the passes' ALU times (0 where a statistic is missing).
double alu_lower_bound_ms(const table::GpuCost& cost);

// The rule on its own. A candidate, its worst training-view error, its bound and, once traced, its estimate.
struct BoundCandidate {
  std::string key;
  double error = 0, bound = 0, est = 0;
  bool traced = false;        // every stage traced: est is its estimate
  bool bound_traced = false;  // the bound is the estimate of the stages traced so far
  bool bound_cached = false;  // the bound takes the traffic that other candidates' traces already simulated
  bool complete = true;       // error is the worst of every view (false: of the views rendered so far, a lower bound)
  std::string beaten_by;      // set when eliminated before every stage was traced
};
// Visits `candidates` by ascending error (then bound, key; the vector is sorted so); a candidate that a fully
// traced one with strictly less error beats (estimate below its bound) is eliminated, the others are passed to
// `trace(chunk, stage)` in chunks of `chunk`, stage by stage (each call raises their est to the worst view
// traced so far). Between stages the partial estimate becomes the bound, since the worst of some views is at
// most the worst of all, and the chunk is checked again: most candidates of a large space are eliminated after
// the first view. `keep` is always traced. Before the last stage, `complete(batch)` (when given) must raise the
// error of each candidate of `batch` (the chunk's candidates with rows on the first training view only) to its
// worst over every view and set `complete`; the chunk is checked again. So a candidate's other views are
// rendered only once its first view's traced estimate has not ruled it out. Rendering them first would save a
// first-view trace (about five stills) only where another view's error decides, and on Sponza and the atrium
// the first view is the worst of 100 % and 89 % of the candidates: it rendered 1749 of Sponza's 2643 on the
// close-up, where this order renders about as many as are traced. A call is a measurement (about 0.7 s of
// fixed cost on Sponza here: the scene, its references, a device).
// Before each stage's trace, `refine(chunk, stage)` (when given) may raise the chunk's bounds on that stage's
// views without tracing (from traffic already simulated), and the chunk is checked again: what it eliminates is
// never traced on that stage.
void eliminate_by_bound(std::vector<BoundCandidate>& candidates, const std::string& keep, int chunk, int stages,
                        const std::function<void(const std::vector<BoundCandidate*>&, int stage)>& trace,
                        const std::function<void(const std::vector<BoundCandidate*>&)>& complete = {},
                        const std::function<void(const std::vector<BoundCandidate*>&, int stage)>& refine = {});

}  // namespace aovar::ship
