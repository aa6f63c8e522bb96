#include "ship/reference_prefetch.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <memory>
#include <utility>

#include "reference/reference.h"
#include "scene/scene.h"

namespace aovar::ship {
namespace {

// Linux gives each thread its own nice value: this one yields to every other thread of the run.
void lowest_priority_for_this_thread() {
  (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 19);  // best effort: only timing changes
}

}  // namespace

ReferencePrefetch::ReferencePrefetch(const measure::MeasureOptions& options, const std::string& scene,
                                     std::vector<std::string> views) {
  if (options.scope.cache_dir.empty() || !options.truth.enabled || views.empty()) return;
  auto promises = std::make_shared<std::map<std::string, std::promise<void>>>();
  for (const std::string& v : views)
    if (!done_.count(v)) done_[v] = (*promises)[v].get_future().share();
  worker_ = std::async(std::launch::async, [options, scene, views = std::move(views), promises] {
    lowest_priority_for_this_thread();
    std::unique_ptr<scene::Scene> loaded;
    try {
      scene::LoadOptions load;
      load.views_file = options.views_file;
      loaded = std::make_unique<scene::Scene>(scene::load_scene(scene, load));
    } catch (...) {  // the round that loads it reports why
    }
    for (const std::string& name : views) {
      auto promise = promises->find(name);
      if (promise == promises->end()) continue;  // named twice: traced once
      try {
        if (loaded) {
          reference::ReferenceOptions ro =
              measure::reference_options(options, options.radius > 0 ? options.radius : loaded->ao_radius);
          ro.alone = true;
          reference::trace_reference(*loaded, loaded->view(name), ro);
        }
      } catch (...) {  // a view the scene lacks, a failed trace: the round that needs it reports it
      }
      promise->second.set_value();
      promises->erase(promise);
    }
  });
}

ReferencePrefetch::~ReferencePrefetch() {
  if (worker_.valid()) worker_.wait();
}

void ReferencePrefetch::wait_for(const std::vector<std::string>& views) {
  for (const std::string& v : views)
    if (auto it = done_.find(v); it != done_.end()) it->second.wait();
}

}  // namespace aovar::ship
