// Which views a calibration fits on and which it holds out: the built-in default and the user's scenes.
#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "calibrate/calibrate.h"
#include "scene/scene.h"

namespace aovar::calibrate {
namespace {

bool contains(const std::vector<std::string>& list, const std::string& s) {
  return std::find(list.begin(), list.end(), s) != list.end();
}

std::string view_names(const scene::Scene& s) {
  std::string out;
  for (const auto& v : s.views) out += (out.empty() ? "" : ", ") + v.name;
  return out;
}

// One scene's split (see split_views).
void split_scene(const scene::Scene& s, const std::vector<std::string>& training_views,
                 const std::vector<std::string>& holdout_views, const std::string& command, ViewSplit& out) {
  const bool has_view_option = command == "calibrate";  // ship trains on every view it does not hold out
  for (const auto& list : {training_views, holdout_views})
    for (const auto& name : list)
      if (std::none_of(s.views.begin(), s.views.end(), [&](const auto& v) { return v.name == name; }))
        throw std::runtime_error(fmt::format("{}: error: scene {} has no view '{}' (its views: {})", command, s.name,
                                             name, view_names(s)));
  for (const auto& name : training_views)
    if (contains(holdout_views, name))
      throw std::runtime_error(fmt::format(
          "{}: error: view '{}' is both a training view (--view) and held out (--holdout-view)", command, name));
  std::size_t trained = 0, held = 0;
  for (std::size_t i = 0; i < s.views.size(); ++i) {
    const std::string& name = s.views[i].name;
    bool hold = !holdout_views.empty()   ? contains(holdout_views, name)
                : !training_views.empty() ? !contains(training_views, name)
                                          : i % 3 == 2;
    bool train = training_views.empty() ? !hold : contains(training_views, name);
    if (train) out.training.push_back({s.name, name}), ++trained;
    if (hold) out.holdout.push_back({s.name, name}), ++held;
  }
  if (trained == 0)
    throw std::runtime_error(fmt::format("{}: error: scene {} has no training view left (its views: {}; {})", command,
                                         s.name, view_names(s),
                                         has_view_option ? "name some with --view" : "hold out fewer with --holdout-view"));
  if (held == 0)
    throw std::runtime_error(fmt::format("{}: error: scene {} has no held-out view (its views: {}; name one with "
                                         "--holdout-view{})",
                                         command, s.name, view_names(s), has_view_option ? " or leave one out of --view" : ""));
}

}  // namespace

ViewSplit builtin_split() {
  ViewSplit out;
  for (const char* s : {"builtin:atrium", "builtin:spheres", "builtin:stairs", "builtin:cornell"}) {
    out.training.push_back({s, "overview"});
    out.training.push_back({s, "closeup"});
    out.holdout.push_back({s, "background"});
  }
  return out;
}

ViewSplit split_views(const std::vector<std::string>& scenes, const std::filesystem::path& views_file,
                      const std::vector<std::string>& training_views, const std::vector<std::string>& holdout_views,
                      const std::string& command) {
  if (scenes.empty()) throw std::runtime_error(command + ": error: no scene to calibrate on (give --scene)");
  ViewSplit out;
  scene::LoadOptions lo;
  lo.views_file = views_file;
  for (const auto& spec : scenes) split_scene(scene::load_scene(spec, lo), training_views, holdout_views, command, out);
  return out;
}

}  // namespace aovar::calibrate
