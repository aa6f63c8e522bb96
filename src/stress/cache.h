#pragma once
// The resumable stress.json: what each check's inputs hash covers, the checks of an earlier run whose
// inputs still match (reused instead of rendered), and the checkpoints that let an interrupted run resume.
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "stress/checks.h"

namespace aovar::stress::detail {

// Variant `v` of the run on `backend` compared with `partner`: its calibrated parameter values and the
// inputs hash of its check on each case (its programs on the backend's target, the parameters, the size,
// the thresholds, the partner, the case and its scene, the backend, fp16).
Member member_of(const Run& run, int v, const std::string& partner, const std::string& backend);

// The checks of an earlier stress.json.
class Previous {
 public:
  Previous() = default;
  // An absent, older or damaged file gives no checks: everything is checked again.
  static Previous read(const std::filesystem::path& stress_json);
  // The earlier checks of every member of `group` on every case (members in order, cases in order), when
  // every one's inputs hash matches; nullopt otherwise: a group is reused whole or rendered whole.
  std::optional<std::vector<Check>> reuse(const Run& run, const Group& group, const std::string& backend) const;

 private:
  std::map<std::string, Check> by_key_;  // variant|case|backend
};

// Writes stress.json mid-run (the checks so far) when the last write is long enough ago: an interruption
// loses at most ten seconds of checks, or 20 writes' time for huge runs. Nothing without an output folder.
class Checkpoints {
 public:
  Checkpoints(const Options& o, const std::vector<std::string>& keys, const std::vector<std::string>& ship);
  // `committed` and the current slice's checks so far.
  void when_due(const Result& committed, const std::vector<Check>& slice);

 private:
  const Options& o_;
  const std::vector<std::string>& keys_;
  const std::vector<std::string>& ship_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
  double write_s_ = 0;  // how long the last write took
};

}  // namespace aovar::stress::detail
