// bench/measure: is `aovar measure` repeatable, and how much does the harness add?
//
// Runs two back-to-back measurements of the same variants on builtin:atrium (no reuse between them) on
// each backend and prints, per backend: Kendall tau-b between the two runs' min-of-N frame times, the
// median and max |delta time| between runs, and the harness overhead in two forms:
//   timed loop:  wall time of the timed round-robin rounds / the summed draw times they reported
//                (command recording, uniform upload, submission, fence waits, timestamp and clock reads)
//   whole run:   wall time of the whole measurement / the summed draw times (adds compiling, pipeline
//                creation, the first-frame JIT, warm-up frames and image read-back and writing)
// Exits non-zero when tau < 0.9 or the timed-loop overhead > 1.3 on any backend (AOVAR_BENCH_SMOKE=1: only
// when a backend measured fewer than two variants).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "measure/measure.h"
#include "smoke.h"

namespace {
using namespace aovar;

double kendall_tau_b(const std::vector<double>& a, const std::vector<double>& b) {
  long concordant = 0, discordant = 0, ties_a = 0, ties_b = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j) {
      double da = a[i] - a[j], db = b[i] - b[j];
      if (da == 0 && db == 0) continue;
      if (da == 0) ++ties_a;
      else if (db == 0) ++ties_b;
      else if ((da > 0) == (db > 0)) ++concordant;
      else ++discordant;
    }
  double n1 = concordant + discordant + ties_a, n2 = concordant + discordant + ties_b;
  return (concordant - discordant) / std::sqrt(n1 * n2);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  measure::MeasureOptions o;
  o.scope.manifest = argc > 1 ? argv[1] : "shader_src/aovar.toml";
  o.scene = "builtin:atrium";
  // 14 variants: the sample-count ladder, then one change at a time from the reference.
  o.globs = {"alchemy-s*-p0-nrg8-zdep-rst-d16-bsep-x1-hp",
             "alchemy-s08-p0-nrg8-zdep-rst-d16-bbil-x1-hp", "alchemy-s08-p0-nrg8-zdep-rst-d16-bno-x1-hp",
             "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x2-hp", "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x4-hp",
             "alchemy-s08-p1-nrg8-zdep-rst-d16-bsep-x1-hp", "alchemy-s08-p0-ndep-zdep-rst-d16-bsep-x1-hp",
             "alchemy-s08-p0-nrg8-zpos-rst-d16-bsep-x1-hp"};
  o.timing.reps = 10;
  const bool smoke = bench_smoke();  // three variants at 64x36, 3 reps: the steps, not the figures
  if (smoke) {
    o.globs = {"alchemy-s0[48]-p0-nrg8-zdep-rst-d16-bsep-x1-hp", "alchemy-s08-p0-nrg8-zdep-rst-d16-bno-x1-hp"};
    o.size = {64, 36};
    o.timing.reps = 3;
    o.timing.warmup = 0;
  }
  o.images = false;
  o.reuse = false;
  std::printf("bench/measure: builtin:atrium %dx%d, %d reps, %d warm-up, LP_NUM_THREADS=%d\n", o.size.width,
              o.size.height, o.timing.reps, o.timing.warmup, o.scope.threads);
  auto progress = [](const std::string& s) { std::fprintf(stderr, "\r\033[K%s", s.c_str()); };

  bool ok = true, measured = true;  // the targets met; every backend measured 2 variants or more
  // One backend at a time, its two runs back to back: a run of the other backend in between changes
  // lavapipe's times (see bench/HISTORY.md, "bench/measure").
  for (const std::string backend : {"lavapipe", "osmesa"}) {
    o.backends = {backend};
    auto a = measure::run_measure(o, progress);
    auto b = measure::run_measure(o, progress);
    std::fprintf(stderr, "\r\033[K");
    std::vector<double> ta, tb, delta;
    std::map<std::string, double> in_b;
    for (const auto& r : b.rows) in_b[r.variant] = r.time_ms.min;
    std::string device = a.devices.empty() ? "" : a.devices[0].device + ", " + a.devices[0].api_version;
    std::printf("\n%s (%s)\n%-46s %9s %9s %7s\n", backend.c_str(), device.c_str(), "variant", "run 1 ms",
                "run 2 ms", "delta");
    for (const auto& r : a.rows) {
      if (!in_b.count(r.variant)) continue;
      ta.push_back(r.time_ms.min);
      tb.push_back(in_b[r.variant]);
      delta.push_back(std::abs(tb.back() - ta.back()) / ta.back());
      std::printf("%-46s %9.2f %9.2f %+6.1f%%\n", r.variant.c_str(), ta.back(), tb.back(),
                  100.0 * (tb.back() - ta.back()) / ta.back());
    }
    if (ta.size() < 2) {
      std::printf("%s: fewer than 2 variants measured in both runs\n", backend.c_str());
      ok = measured = false;
      continue;
    }
    double tau = kendall_tau_b(ta, tb);
    double loop_wall = 0, loop_sum = 0;
    for (const auto* res : {&a, &b})
      for (const auto& run : res->runs) loop_wall += run.timed_wall_s, loop_sum += run.timed_sum_s;
    double overhead_loop = loop_wall / loop_sum;
    std::printf("%s: %zu variants, Kendall tau %.3f, median |delta| %.1f%%, max |delta| %.1f%%, "
                "harness overhead (timed loop) %.3fx\n",
                backend.c_str(), ta.size(), tau, 100 * median(delta),
                100 * *std::max_element(delta.begin(), delta.end()), overhead_loop);
    ok &= tau >= 0.9 && overhead_loop <= 1.3;
    double sum = 0, prepare = 0, warmup = 0, readback = 0;
    for (const auto& run : a.runs)
      sum += run.timed_sum_s, prepare += run.prepare_s, warmup += run.warmup_s, readback += run.readback_s;
    std::printf("%s run 1 wall %.1f s: compile %.1f s, prepare %.1f s, first frame + warm-up %.1f s, timed draws "
                "%.1f s, read-back %.1f s; whole-run overhead %.2fx the timed draw time\n",
                backend.c_str(), a.wall_s, a.compile_s, prepare, warmup, sum, readback, a.wall_s / sum);
  }
  std::printf("%s%s\n", ok ? "PASS: tau >= 0.9 and timed-loop overhead <= 1.3x on every backend"
                           : "FAIL: a target was missed (see above)",
              smoke ? " (smoke: not judged)" : "");
  return measured && (ok || smoke) ? 0 : 1;
}
