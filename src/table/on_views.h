#pragma once
// The rows a decision was made on: ship decides on its training views for the race and on its held-out views
// for the choice, and a ship table's report and build read the same rows back.
#include <string>
#include <vector>

#include "table/table.h"

namespace aovar::table {

// The rows of `table` on `views`, in table order, with its meta.
CostTable rows_on_views(const CostTable& table, const std::vector<std::string>& views);

// What a table's choice for `target` (a GPU, or a measured backend) was made among: for a table `aovar ship`
// wrote, the rows on its held-out views (meta.ship.holdout_views) of the variants that survived its search
// on that target (meta.ship.choices[].survivors, where a search for several GPUs recorded them); any other
// table whole. Throws std::runtime_error naming meta.ship when those members are malformed.
CostTable decided_rows(const CostTable& table, const std::string& target);

}  // namespace aovar::table
