// The cost-table reader, and what `report` and `select` do with what it returns.
#include "fuzz_support.h"
#include "table/table.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = aovar::fuzz::input_file(data, size, "cost_table.json");
  aovar::fuzz::expect_clean([&] {
    aovar::table::CostTable t = aovar::table::read_table(path);
    aovar::table::mark_pareto(t);
    aovar::table::to_markdown(t);
    aovar::table::to_csv(t);
  });
  return 0;
}
