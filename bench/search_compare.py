#!/usr/bin/env python3
"""bench/search: compares `aovar ship`'s race with an exhaustive sweep of the same subspace (issue 35).

Usage: search_compare.py SHIP_OUT EXHAUSTIVE_TABLE
Both measured with the same calibration (the one ship fitted) on the same views. Within the exhaustive table
(one run, so times compare without drift between runs):
  - the exhaustive front over the training views (each variant's worst training view: max rmse, max paired
    time), as `aovar select` aggregates;
  - recall: the share of that front that ship kept, or that a variant ship kept covers (rmse and time each
    within 2 %, select's tolerance, of the front variant's);
  - ship's eliminations that were on the exhaustive front (what the race lost).
Prints one line per figure; exit 0.
"""
import json
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


if __name__ == "__main__":
    main()
