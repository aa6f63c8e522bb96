#!/usr/bin/env python3
"""What the order of the race's batches leaves untimed, from a finished `aovar ship` run (issue 35).

The race retires a candidate on a view once a more accurate one is faster beyond the noise: one of its own
batch, in the same rounds, or one timed in an earlier batch, against the reference every batch times
(measure::Retire). A row whose beater is timed in a *later* batch runs on to its target or cap, so the order
of the batches (ship::screen_ranks: the screen's front first) decides how much is timed for nothing. This
prints, per view of OUT/race, the rows, how each one's timing ended and the frame time it took (rounds x
median), and that headroom: the rows timed to their target or cap that a more accurate row of another batch
beats, and their frame time (the most any better order could save, less the rounds a retirement needs).

Rows of different batches share no rounds, so "beats beyond the noise" compares each row's interval against
the baseline (which every batch times): the two intervals, rel_time_median x (1 +- ci_half_width), are
disjoint. Same-code copies (their rows are copies) and the baseline's own row are left out.

Usage: bench/race_headroom.py OUT   (OUT: the ship --out folder of a measured backend)
"""
import collections
import glob
import json
import sys


def rows_of(out):
    files = glob.glob(f"{out}/race/measure/*/measure.json")
    if not files:
        sys.exit(f"race_headroom: no {out}/race/measure/*/measure.json: give the --out folder of a measured ship run")
    rows = []
    for f in files:
        m = json.load(open(f))
        rows += [r for r in m["rows"] + m.get("kept_rows", []) if isinstance(r, dict)]
    return rows


def candidate(r):
    if r.get("is_baseline") or r.get("same_code_as") or not r.get("error"):
        return None
    half = r.get("ci_half_width") or 0.0
    return {"variant": r["variant"], "rmse": r["error"]["rmse"], "lo": r["rel_time_median"] * (1 - half),
            "hi": r["rel_time_median"] * (1 + half), "stop": r.get("stop"), "batch": r["rounds"]["id"],
            "frame_s": r["time_ms"]["n"] * r["time_ms"]["median"] / 1000}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__.strip().splitlines()[-1])
    by_view = collections.defaultdict(list)
    for r in rows_of(sys.argv[1]):
        c = candidate(r)
        if c:
            by_view[r["view"]].append(c)
    print("view        rows  retired  target/cap  frame s: retired  target/cap  | beaten across batches: rows  frame s")
    for view, cs in sorted(by_view.items()):
        timed = [c for c in cs if c["stop"] != "dominated"]
        across = [c for c in timed
                  if any(d["rmse"] < c["rmse"] and d["hi"] < c["lo"] and d["batch"] != c["batch"] for d in cs)]
        print(f"{view:10s} {len(cs):5d} {len(cs) - len(timed):8d} {len(timed):11d}"
              f" {sum(c['frame_s'] for c in cs if c['stop'] == 'dominated'):16.0f} {sum(c['frame_s'] for c in timed):11.0f}"
              f"  | {len(across):34d} {sum(c['frame_s'] for c in across):8.0f}")


if __name__ == "__main__":
    main()
