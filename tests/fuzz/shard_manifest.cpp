// The shard manifest reader (shard.json, issue 34): the whole-number fields, the pinned row set, and the
// checks merge runs on a set of manifests.
#include "fuzz_support.h"
#include "shard/manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = aovar::fuzz::input_file(data, size, "shard.json");
  aovar::fuzz::expect_clean([&] {
    const aovar::shard::ShardManifest m = aovar::shard::read_manifest(path);
    aovar::shard::check_pinned_rows("shard", m, "cost_table.json", {"a|s|v|lavapipe|64x36|2"});
    aovar::shard::check_shard_set({{"shard", m}});
    aovar::shard::balance_summary({{"shard", m}});
  });
  return 0;
}
