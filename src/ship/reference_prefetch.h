#pragma once
// The references a ship needs after its screen, traced during it (issue 55). With a GPU target the screen renders
// the first training view's stills and then estimates, both leaving part of the machine idle (the stills about a
// third of it, the estimate about half), while the rounds after it start by ray-tracing: the other training views'
// references when the first chunk is rendered on them, the held-out views' in the front round. Traced on a thread
// of their own at the lowest priority, on that thread alone (reference::ReferenceOptions::alone), they take only
// the idle time, and land in the reference cache (reference/cache.h), where those rounds find them.
#include <future>
#include <map>
#include <string>
#include <vector>

#include "measure/measure.h"

namespace aovar::ship {

class ReferencePrefetch {
 public:
  // Starts tracing, in order, the references of `views` of `scene` that a round with `options` (its measure
  // options) would score against, into options' cache. Nothing without a cache.
  ReferencePrefetch(const measure::MeasureOptions& options, const std::string& scene, std::vector<std::string> views);
  ~ReferencePrefetch();  // waits for the thread: it reads the options and writes the cache
  ReferencePrefetch(const ReferencePrefetch&) = delete;
  ReferencePrefetch& operator=(const ReferencePrefetch&) = delete;

  // Waits until the references of `views` are cached, or failed: a failure is dropped here, and the round that needs
  // the reference traces it again and reports its own error. A view never asked for does not wait.
  void wait_for(const std::vector<std::string>& views);

 private:
  std::map<std::string, std::shared_future<void>> done_;  // by view
  std::future<void> worker_;
};

}  // namespace aovar::ship
