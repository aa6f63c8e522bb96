#!/usr/bin/env python3
"""bench/search: compares `aovar ship`'s race with an exhaustive sweep of the same subspace (issue 35).

Usage: search_compare.py SHIP_OUT EXHAUSTIVE_TABLE
Both measured with the same calibration (the one ship fitted) on the same views. Within the exhaustive table
(one run, so times compare without drift between runs):
  - the exhaustive front over the training views (each variant's worst training view: max rmse, max paired
    time), as `aovar select` aggregates;
  - recall: the share of that front that ship kept, or that a variant ship kept covers (rmse and time each
    within 2 %, select's tolerance, of the front variant's);
  - ship's eliminations that were on the exhaustive front (what the race lost);
  - how far a pair's time ratio moves between ship's screen and the exhaustive sweep (the drift that
    --race-margin must cover), per view: median and 95th percentile over every pair of screened variants;
  - ship's eliminations re-read at other margins: an elimination stands at margin R only when the lower bound
    of its slowdown's 95 % interval lies above R (race.cpp's rule), so the counts need no re-run.
Prints one line per figure; exit 0.
"""
import itertools
import json
import os
import re
import statistics
import sys


def worst_by_variant(rows, views):
    out = {}
    for r in rows:
        if r.get("predicted") or not r.get("error") or r["view"] not in views or r.get("same_code_as"):
            continue
        t = r["time_ms"].get("paired") or r["time_ms"]["min"]
        e = r["error"]["rmse"]
        w = out.setdefault(r["variant"], [0.0, 0.0])
        w[0], w[1] = max(w[0], t), max(w[1], e)
    return out


def front(points):
    keys = sorted(points, key=lambda k: (points[k][0], points[k][1]))
    out, best = [], float("inf")
    for k in keys:
        if points[k][1] < best:
            out.append(k)
            best = points[k][1]
    return out


def paired_times(rows):
    """(view, variant) -> paired time (the time on the rounds' common scale) of a table's measured rows."""
    out = {}
    for r in rows:
        if r.get("predicted") or r.get("same_code_as"):
            continue
        t = r["time_ms"].get("paired") or r["time_ms"].get("min")
        if t:
            out[(r["view"], r["variant"])] = t
    return out


def percentile(values, q):
    v = sorted(values)
    return v[min(len(v) - 1, int(q * (len(v) - 1) + 0.5))]


def print_drift(screen_rows, exhaustive_rows):
    a, b = paired_times(screen_rows), paired_times(exhaustive_rows)
    for view in sorted({v for v, _ in a}):
        keys = sorted(k for (v, k) in a if v == view and (view, k) in b)
        drift = [abs((a[(view, x)] / a[(view, y)]) / (b[(view, x)] / b[(view, y)]) - 1.0)
                 for x, y in itertools.combinations(keys, 2)]
        if drift:
            print(f"pair-ratio drift, screen against exhaustive, {view}: {len(keys)} variants, {len(drift)} pairs, "
                  f"median {100 * statistics.median(drift):.1f} %, p95 {100 * percentile(drift, 0.95):.1f} %")


def print_margins(meta, front_variants):
    bounds = []  # (round, lower bound of the slowdown, on the exhaustive front)
    for e in meta["eliminated"]:
        m = re.search(r"\(([0-9.]+)x \[([0-9.]+), ([0-9.]+)\]", e["reason"])
        if m and e["reason"].startswith("slower"):
            bounds.append((e["round"], float(m.group(2)), e["variant"] in front_variants))
    if not bounds:
        return
    used = meta.get("race_margin", 1.0)
    for margin in (1.0, 1.05, 1.10, 1.20):
        if margin < used:
            continue
        stand = [b for b in bounds if b[1] > margin]
        by_round = ", ".join(f"{r} {sum(1 for b in stand if b[0] == r)} of {sum(1 for b in bounds if b[0] == r)}"
                             for r in sorted({b[0] for b in bounds}))
        print(f"at --race-margin {margin:.2f}: eliminations that stand: {by_round}; "
              f"front members still lost {sum(1 for b in stand if b[2])}")


def main():
    ship_dir, exhaustive_path = sys.argv[1], sys.argv[2]
    ship = json.load(open(f"{ship_dir}/cost_table.json"))
    meta = ship["meta"]["ship"]
    training = set(meta["training_views"])
    kept = {r["variant"] for r in ship["rows"]}
    rows = json.load(open(exhaustive_path))["rows"]
    points = worst_by_variant(rows, training)
    f = front(points)
    covered = []
    for v in f:
        t, e = points[v]
        if v in kept or any(k in points and points[k][0] <= 1.02 * t and points[k][1] <= 1.02 * e for k in kept):
            covered.append(v)
    lost = [e for e in meta["eliminated"] if e["variant"] in f]
    print(f"exhaustive: {len(points)} variants, front over the training views {len(f)}")
    print(f"ship kept {len(kept)}; rounds: " + ", ".join(
        f"{r['name']} {r['candidates']} -> {r['candidates'] - r['eliminated']} ({r['seconds']:.0f} s)" for r in meta["rounds"]))
    print(f"recall: {len(covered)}/{len(f)} = {100.0 * len(covered) / max(1, len(f)):.1f} % of the exhaustive front kept or covered")
    for e in lost:
        print(f"  lost from the front: {e['variant']} ({e['round']}: {e['reason']})")
    screen = f"{ship_dir}/screen/cost_table.json"  # none when one race batch held every candidate
    if os.path.exists(screen):
        print_drift(json.load(open(screen))["rows"], rows)
    print_margins(meta, set(f))


if __name__ == "__main__":
    main()
