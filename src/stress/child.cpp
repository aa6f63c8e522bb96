#include "stress/child.h"

#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "stress/report.h"
#include "util/isolated.h"

namespace aovar::stress::detail {
namespace {

// The child's side: render, one line per event; an exception becomes an 'e' line and status 2.
int render_and_stream(const Run& run, const std::string& backend_name, const std::vector<Group>& groups,
                      util::LineWriter& out) {
  // Test hook: a check line the parent cannot read (a child whose memory went bad) must cost that slice's
  // variant, not the run (tests/stress/test_stress.cpp).
  const char* garble = std::getenv("AOVAR_STRESS_TEST_GARBLE");
  try {
    render_groups(
        run, backend_name, groups, [&](const std::string& key) { out.line("v " + key); },
        [&](const Check& ch) {
          out.line(garble && ch.variant == garble ? "c {\"variant\": \x01" : "c " + check_json(ch).dump());
        },
        true);
    return 0;
  } catch (const std::exception& e) {
    out.line(std::string("e ") + e.what());
    return 2;
  }
}

ChildEnd ending(const util::ChildOutcome& how, const std::string& error, const std::string& garbled) {
  ChildEnd end;
  if (!garbled.empty()) {  // a whole line that is not a check: the child's memory is not to be trusted
    end.crashed = true;
    end.message = fmt::format("the renderer sent a line that is not a check ({})", garbled);
  } else if (how.signal != 0) {
    end.crashed = true;
    end.message = fmt::format("the renderer crashed (signal {}, {})", how.signal, strsignal(how.signal));
  } else if (how.cut_off) {  // died mid-write without a signal: the check in flight is lost, as in a crash
    end.crashed = true;
    end.message = fmt::format("the renderer stopped mid-line (exit status {})", how.exit_code);
  } else if (how.exit_code != 0) {
    end.crashed = error.empty();
    end.message = error.empty() ? fmt::format("the renderer exited with status {}", how.exit_code) : error;
  }
  return end;
}

}  // namespace

ChildEnd render_in_child(const Run& run, const std::string& backend_name, const std::vector<Group>& groups,
                         const Starting& starting, const Emit& emit) {
  std::string error, garbled;
  const auto how = util::run_isolated(
      [&](util::LineWriter& out) { return render_and_stream(run, backend_name, groups, out); },
      [&](const std::string& line) {
        // After a garbled line nothing the child says counts: the slice ends there, and the variant it was
        // rendering (the last 'v') is the one blamed.
        if (line.size() < 2 || !garbled.empty()) return;
        const std::string rest(line, 2);  // after the tag and its space
        if (line[0] == 'v') starting(rest);
        else if (line[0] == 'c') {
          std::optional<Check> check;
          try {
            check = check_from_json(nlohmann::json::parse(rest));
          } catch (const std::exception& e) {  // parse or field errors: a crashed slice, not a crashed run
            garbled = fmt::format("{}: {}", rest.substr(0, 60), e.what());
          }
          if (check) emit(*check);
        }
        else if (line[0] == 'e') error = rest;
      });
  return ending(how, error, garbled);
}

}  // namespace aovar::stress::detail
