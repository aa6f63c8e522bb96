# shellcheck shell=bash
# Sourced by every bench script (from the repository root): the build folder, the build step and the smoke
# mode. AOVAR_BUILD picks the build folder (default build). AOVAR_BENCH_SMOKE=1 runs the script's own steps
# with the smallest sizes, repetitions and selections that still exercise each of them (seconds, not
# minutes; its figures mean nothing) and prints targets without judging them: ctest's bench-smoke label
# runs every script so (tests/bench_smoke/). AOVAR_BENCH_PREBUILT=1 skips the build step and only checks the
# binaries are there (ctest builds them before the tests run; a configure under a running ctest would not do).
build=${AOVAR_BUILD:-build}
smoke=${AOVAR_BENCH_SMOKE:-0}
[ "$smoke" = 0 ] || [ "$smoke" = 1 ] || { echo "AOVAR_BENCH_SMOKE must be 0 or 1, not '$smoke'" >&2; exit 2; }

# bench_build TARGET...: configures and builds the targets in $build (aovar is $build/aovar, the others
# $build/bench/TARGET).
bench_build() {
  if [ "${AOVAR_BENCH_PREBUILT:-0}" = 1 ]; then
    local t bin
    for t in "$@"; do
      bin=$build/bench/$t
      [ "$t" = aovar ] && bin=$build/aovar
      [ -x "$bin" ] || { echo "AOVAR_BENCH_PREBUILT=1 but $bin is not built (ninja -C $build $t)" >&2; exit 2; }
    done
    return 0
  fi
  cmake -S . -B "$build" -G Ninja >/dev/null
  ninja -C "$build" "$@" >/dev/null
}

# smoke_or FULL SMOKE: FULL, or SMOKE in smoke mode.
smoke_or() { if [ "$smoke" = 1 ]; then echo "$2"; else echo "$1"; fi; }
