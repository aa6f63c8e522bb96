#pragma once
// The top of a ship report (report.h): the decision in words and numbers, the images that make its case on
// the held-out view, and the funnel of eliminations. The evidence (fronts, charts, pairs) follows it.
#include <filesystem>
#include <string>
#include <vector>

#include "report/ship_decision.h"
#include "table/table.h"

namespace aovar::report {

// What to ship, its time with the 95 % interval, its held-out error, its ties, the baseline it replaces, the
// runners-up and the `aovar generate` line. The elements a reader must see first carry ids (choice-key,
// choice-time, choice-error, build-line) that the report's test finds on the first screen.
std::string decision_html(const ShipDecision& d);
// A search for several GPUs: their choices side by side ("" for one).
std::string choices_html(const std::vector<ShipDecision>& all);
std::string choices_markdown(const std::vector<ShipDecision>& all);
std::string decision_markdown(const ShipDecision& d);

// The chosen variant, the baseline and the reference on the first held-out view, then both error maps, each
// at its full resolution. `dir`: the folder the table's image paths are relative to.
std::string decision_images_html(const ShipDecision& d, const std::filesystem::path& dir);
// report.md links them: `images` is the folder the table's image paths are relative to, as seen from report.md.
std::string decision_images_markdown(const ShipDecision& d, const std::filesystem::path& images);

// How many variants each step left, and why; then every elimination of meta.ship.eliminated (bounded).
std::string funnel_html(const ShipDecision& d, const table::CostTable& t);
std::string funnel_markdown(const ShipDecision& d);

}  // namespace aovar::report
