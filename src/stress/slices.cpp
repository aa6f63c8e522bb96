#include "stress/slices.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "stress/child.h"

namespace aovar::stress::detail {

void Tally::starting(const std::string& backend, const std::string& key) {
  const auto elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string eta = rendered_ > 0 ? fmt::format(", ETA {:.0f} s", elapsed / rendered_ * (total_ - done_)) : "";
  if (say_) say_(fmt::format("[{}/{} variants{}] {}: {}", done_ + 1, total_, eta, backend, key));
  ++done_, ++rendered_;
}

namespace {

class SliceRenderer {
 public:
  SliceRenderer(const Run& run, const std::string& backend, std::vector<Group> pending, Result& res, Tally& tally,
                Checkpoints& checkpoints)
      : run_(run), backend_(backend), pending_(std::move(pending)), res_(res), tally_(tally), checkpoints_(checkpoints) {}

  void render_all() {
    for (std::size_t next = 0; next < pending_.size();) {
      const std::size_t end = slice_end(next);
      const ChildEnd how = render_slice(next, end);
      if (!how.crashed && !how.message.empty()) throw std::runtime_error("stress: " + backend_ + ": " + how.message);
      if (how.crashed) {
        next += settle_crash(next, end, how.message);
        continue;
      }
      res_.checks.insert(res_.checks.end(), slice_checks_.begin(), slice_checks_.end());
      next = end;
    }
  }

 private:
  // One past the last group of the slice starting at `next`: at least one group, at most
  // renders_per_process renders (variants x cases).
  std::size_t slice_end(std::size_t next) const {
    std::size_t end = next;
    for (long renders = 0; end < pending_.size(); ++end) {
      renders += static_cast<long>(pending_[end].size() * run_.cases.size());
      if (end > next && run_.o.renders_per_process > 0 && renders > run_.o.renders_per_process) break;
    }
    return end;
  }

  ChildEnd render_slice(std::size_t next, std::size_t end) {
    const std::vector<Group> slice(pending_.begin() + static_cast<long>(next), pending_.begin() + static_cast<long>(end));
    slice_checks_.clear();
    current_.clear();
    const Starting starting = [&](const std::string& key) {
      current_ = key;
      tally_.starting(backend_, key);
    };
    const Emit emit = [&](const Check& ch) {
      slice_checks_.push_back(ch);
      checkpoints_.when_due(res_, slice_checks_);
    };
    if (run_.o.renders_per_process > 0) return render_in_child(run_, backend_, slice, starting, emit);
    render_groups(run_, backend_, slice, starting, emit, false);
    return {};
  }

  // The child died rendering current_: keep the checks of the groups before its group, fail it on the case
  // in flight (and say which cases it never reached), and leave its group pending without it, to render
  // again. Returns how many groups of the slice are done.
  std::size_t settle_crash(std::size_t next, std::size_t end, const std::string& message) {
    auto holds_current = [&](const Member& m) { return run_.keys[m.v] == current_; };
    std::size_t g = next;
    while (g < end && std::none_of(pending_[g].begin(), pending_[g].end(), holds_current)) ++g;
    if (g == end) throw std::runtime_error("stress: " + backend_ + ": " + message + " before its first variant");
    Group& group = pending_[g];
    std::set<std::string> redo;
    for (const Member& m : group) redo.insert(run_.keys[m.v]);
    std::size_t reached = 0;  // cases the crashed variant finished
    for (const Check& ch : slice_checks_) {
      if (ch.variant == current_) ++reached;
      if (!redo.count(ch.variant) || ch.variant == current_) res_.checks.push_back(ch);
    }
    auto crashed = std::find_if(group.begin(), group.end(), holds_current);
    fail_unfinished(*crashed, reached, message);
    tally_.again(static_cast<std::size_t>(crashed - group.begin()));  // the members before it render again
    group.erase(crashed);
    // Members compared with it compare with nothing now: say so (no partner) rather than report a
    // comparison that never happened (pair_max 0 reads as identical images).
    for (Member& m : group)
      if (m.partner == current_) m.partner.clear();
    return g - next + (group.empty() ? 1 : 0);
  }

  // The crashed member's checks from case `reached` on: the case in flight, then those never rendered.
  void fail_unfinished(const Member& crashed, std::size_t reached, const std::string& message) {
    for (std::size_t ci = reached; ci < run_.cases.size(); ++ci) {
      Check ch;
      ch.variant = current_, ch.case_name = run_.cases[ci].name, ch.backend = backend_, ch.partner = crashed.partner;
      ch.inputs_hash = crashed.hashes[ci];
      ch.failure = ci == reached ? message + " rendering this case"
                                 : "not rendered: " + message + " on case " + run_.cases[reached].name;
      res_.checks.push_back(ch);
    }
  }

  const Run& run_;
  const std::string& backend_;
  std::vector<Group> pending_;
  Result& res_;
  Tally& tally_;
  Checkpoints& checkpoints_;
  std::vector<Check> slice_checks_;  // the current slice's checks so far
  std::string current_;              // the variant being rendered
};

}  // namespace

void render_pending(const Run& run, const std::string& backend_name, std::vector<Group> pending, Result& res,
                    Tally& tally, Checkpoints& checkpoints) {
  SliceRenderer(run, backend_name, std::move(pending), res, tally, checkpoints).render_all();
}

}  // namespace aovar::stress::detail
