// The cost-table reader with its validator, and what `report` and `select` do with what it returns (the
// selection over any verdict graph: issue 34's cycles).
#include "decide/pareto.h"
#include "decide/select.h"
#include "fuzz_support.h"
#include "table/table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = aovar::fuzz::input_file(data, size, "cost_table.json");
  aovar::fuzz::expect_clean([&] {
    aovar::table::CostTable t = aovar::table::read_table(path);
    aovar::decide::mark_pareto(t);
    aovar::table::to_markdown(t);
    aovar::table::to_csv(t);
    aovar::decide::worst_view(t.rows);
    aovar::decide::SelectQuery q;
    q.max_error = 0.15;
    aovar::decide::select(t, q);
  });
  aovar::fuzz::expect_clean([&] {
    aovar::decide::SelectQuery q;
    q.budget_ms = 2;
    aovar::decide::select(aovar::table::read_table(path), q);
  });
  return 0;
}
