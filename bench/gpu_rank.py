#!/usr/bin/env python3
"""bench/gpu_rank.py: per GPU family, Spearman rank correlation of measured GPU time against RADV's est_ms
(gpu.json) and against lavapipe time, and of lavapipe time against est_ms, with n. Used by bench/gpu.
Usage: gpu_rank.py GPU_MEASURE_JSON LAVAPIPE_MEASURE_JSON GPU_JSON   (GPU_JSON may be "-": no estimates)
Exit 2 when a file is missing or gpu.json has no families[].variants[].estimate.est_ms."""
import json
import sys


def average_ranks(values):
    """Ranks 1..n, ties sharing the average of the ranks they span."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    ranks = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            ranks[order[k]] = (i + j) / 2 + 1
        i = j + 1
    return ranks


def spearman(xs, ys):
    """Pearson correlation of the average ranks; None below 3 pairs or for a constant side."""
    if len(xs) < 3:
        return None
    rx, ry = average_ranks(xs), average_ranks(ys)
    mx, my = sum(rx) / len(rx), sum(ry) / len(ry)
    sxy = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    sxx = sum((a - mx) ** 2 for a in rx)
    syy = sum((b - my) ** 2 for b in ry)
    return None if sxx == 0 or syy == 0 else sxy / (sxx * syy) ** 0.5


def load(path, what):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"bench/gpu: cannot read {what} {path} ({e}): run bench/gpu again")


def times_by_variant(measure):
    """Minimum frame time (ms) per variant key; the timing-only baseline row is left out."""
    return {r["variant"]: r["time_ms"]["min"] for r in measure["rows"] if not r.get("is_baseline")}


def estimates_by_family(gpu):
    """{family: {key: est_ms}}, read exactly at families[].variants[].key / .estimate.est_ms."""
    families = {}
    for fam in gpu.get("families", []):
        est = {v["key"]: v["estimate"]["est_ms"] for v in fam.get("variants", [])
               if isinstance(v.get("estimate"), dict) and "est_ms" in v["estimate"]}
        families[fam.get("family", fam.get("name", "?"))] = est
    return families


def line(label, xs_by_key, ys_by_key):
    keys = sorted(set(xs_by_key) & set(ys_by_key))
    rho = spearman([xs_by_key[k] for k in keys], [ys_by_key[k] for k in keys])
    return f"  {label:<28} rho = {'n/a' if rho is None else f'{rho:+.3f}'}  (n = {len(keys)})"


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    gpu_measure, lvp_measure = load(sys.argv[1], "measure.json"), load(sys.argv[2], "measure.json")
    gpu_dev = gpu_measure["devices"][0]
    print(f"measured: {gpu_dev['device']} ({gpu_dev['driver']}, timing: {gpu_dev.get('timing', '?')})")
    gpu_t, lvp_t = times_by_variant(gpu_measure), times_by_variant(lvp_measure)
    print(line("GPU time vs lavapipe time", gpu_t, lvp_t))
    if sys.argv[3] == "-":
        print("bench/gpu: no gpu.json (aovar analyze --gpu failed, see above): no correlations against est_ms")
        return 2
    families = estimates_by_family(load(sys.argv[3], "gpu.json"))
    if not families or not any(families.values()):
        print(f"bench/gpu: {sys.argv[3]} has no families[].variants[].estimate.est_ms: this aovar's analyze --gpu "
              "does not estimate times yet (merge the RADV estimate, then run bench/gpu again)")
        return 2
    for family, est in families.items():
        print(f"{family}:")
        print(line("GPU time vs RADV est_ms", gpu_t, est))
        print(line("lavapipe time vs RADV est_ms", lvp_t, est))
    return 0


if __name__ == "__main__":
    sys.exit(main())
