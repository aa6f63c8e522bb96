#!/usr/bin/env python3
"""Inputs at the scale the whole-space search writes (issue 34, point 5), for timing aovar on them.

  generate.py table N OUT.json [full]
                                   a cost_table.json of N rows: up to 30,000 variants of the default space x
                                   views (3, or as many as N needs) of one scene on lavapipe, timed in
                                   batches of 8 against the first variant (15 rounds each, as measure writes
                                   them: ratios, paired time, sign-test intervals), each with an error;
                                   `full`: each row also has what a sweep with --reference writes besides
                                   (its static cost from the SPIR-V and the error's breakdown), about 2x the
                                   bytes
  generate.py manifest N OUT.toml  the default manifest (shader_src/aovar.toml) plus N `skip` rules inside
                                   what its rules already drop (24+ samples at quarter resolution), each
                                   matching some point (a rule that matches none is an error), so `aovar list`
                                   prints the default variants but tests every rule at every point; its
                                   templates are named as in shader_src/, so write it into a copy of it

Deterministic (a fixed seed); writes only OUT. The figures and the commands: bench/README.md.
"""
import json
import math
import random
import sys
import zlib
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCENE, BACKEND, SIZE, THREADS = "builtin:atrium", "lavapipe", "64x36", 2
ROUNDS, BATCH, BASELINE_MS = 15, 8, 1.0
BASELINE_KEY = ""
ALGORITHMS = ["alchemy", "unsharp", "sao", "hbao", "gtao", "crytek", "sc2", "homebrew", "vo", "vbao"]


def sign_test_interval(sorted_ratios):
    """[x_(k), x_(n+1-k)] for the largest k with coverage >= 95 % (docs/confidence.md); None below 6."""
    n = len(sorted_ratios)
    if n < 6:
        return None
    best = None
    for k in range(1, n // 2 + 1):
        tail = sum(math.comb(n, i) for i in range(k)) / 2 ** n
        if 1 - 2 * tail >= 0.95:
            best = k
    return None if best is None else [sorted_ratios[best - 1], sorted_ratios[n - best]]


AXES = {  # the default manifest's [axes], in order
    "algorithm": ALGORITHMS, "samples": [4, 6, 8, 12, 16, 24, 32], "progressive": [False, True],
    "normals": ["rgb8", "rg8", "oct16", "depth"], "position": ["depth", "position"],
    "reconstruct": ["similar_triangles", "inverse_projection"], "depth_format": ["r16f", "r32f"],
    "blur": ["none", "separable", "bilateral"], "resolution": [1.0, 0.5, 0.25], "precision": ["highp", "mediump"],
}
SPACE = math.prod(len(v) for v in AXES.values())  # 40,320 points


def axes_of(point):
    """The point-th of the product (mixed radix, last axis fastest) as {axis: canonical text}."""
    out = {}
    for name in reversed(list(AXES)):
        values = AXES[name]
        v = values[point % len(values)]
        point //= len(values)
        out[name] = ("true" if v else "false") if isinstance(v, bool) else f"{v:g}" if isinstance(v, float) else str(v)
    return dict(reversed(list(out.items())))


def key_of(a):
    tokens = {"rgb8": "nrgb8", "rg8": "nrg8", "oct16": "noct", "depth": "ndep"}
    return "-".join([a["algorithm"], f"s{int(a['samples']):02d}", "p1" if a["progressive"] == "true" else "p0",
                     tokens[a["normals"]], "zdep" if a["position"] == "depth" else "zpos",
                     "rst" if a["reconstruct"] == "similar_triangles" else "rip",
                     "d16" if a["depth_format"] == "r16f" else "d32",
                     {"none": "bno", "separable": "bsep", "bilateral": "bbil"}[a["blur"]],
                     f"x{round(1 / float(a['resolution']))}", "hp" if a["precision"] == "highp" else "mp"])


def static_cost(cost):
    """A sweep's "static" object (table/static_cost.h), its counts growing with the row's cost."""
    def counts(k):
        return {"alu": round(200 * k), "branches": 16.0, "cmp_select": 31.0, "div": 17.0,
                "fetches": {"depth": round(4 * k), "history": 0.0, "input": 0.0, "normal": 1.0, "position": 0.0,
                            "prefilter": 0.0},
                "fma": 0.0, "loops": {"constant": 1, "dynamic": 0, "unrolled": 0}, "projections": 0.0,
                "transcendental": 17.0, "unprojections": 5.0}

    def weighted(k):
        return {"alu": round(200 * k), "branches": 16.0, "cmp_select": 31.0, "div": 17.0, "fetches": round(4 * k),
                "prefilter_fetches": 0.0, "transcendental": 17.0}
    return {"ao": counts(cost), "passes": counts(cost * 1.3), "ao_bytes_per_pixel": 12.0,
            "weighted": {"ao": weighted(cost), "others": weighted(cost * 0.3)}, "work_per_pixel": round(250 * cost)}


def breakdown(rmse, rng):
    """The error's breakdown (metrics/breakdown.h): per part its pixel share, rmse, error share and mean."""
    out = {"edge_band_px": 17.1, "split_depth": 9.09}
    for part, share in (("edge", 0.18), ("interior", 0.82), ("near", 0.5), ("far", 0.5), ("light", 0.05),
                        ("dark", 0.64)):
        out[part] = {"pixel_share": share, "rmse": rmse * rng.uniform(0.7, 1.4), "error_share": share,
                     "mean_error": -rmse * rng.uniform(0.2, 0.6)}
    return out


def row(variant, axes, view, batch, ratios, rmse, rng):
    ratios_sorted = sorted(ratios)
    median = ratios_sorted[len(ratios) // 2]
    ci = sign_test_interval(ratios_sorted)
    frames = sorted(r * BASELINE_MS * (1 + 0.01 * rng.random()) for r in ratios)
    is_baseline = batch == "all"
    return {
        "variant": variant, "axes": axes, "spirv_hash": f"{zlib.crc32(variant.encode()):08x}",
        "scene": SCENE, "view": view, "backend": BACKEND, "device": "llvmpipe (generated)", "driver": "Mesa (generated)",
        "size": SIZE, "threads": THREADS, "static": None, "gpu": {},
        "time_ms": {"min": frames[0], "median": frames[len(frames) // 2], "p90": frames[int(0.9 * (len(frames) - 1))],
                    "n": len(frames), "paired": median * BASELINE_MS,
                    "paired_ci": None if is_baseline or ci is None else [ci[0] * BASELINE_MS, ci[1] * BASELINE_MS]},
        "rel_time": ratios_sorted[0], "rel_time_median": median, "rel_time_ci": None if is_baseline else ci,
        "rounds": {"scale": f"{BASELINE_KEY}@{SCENE}/{view}/{BACKEND}/llvmpipe/{SIZE}/{THREADS}", "id": batch, "ratios": ratios},
        "same_code_as": "",
        "error": {"rmse": rmse, "mae": rmse * 0.8, "psnr": -20 * math.log10(rmse), "ssim": 1 - rmse, "bias": -rmse / 3,
                  "max": min(1.0, rmse * 6)},
        "health": {"nan": 0, "inf": 0, "out_of_range": 0}, "pareto": False, "predicted": False, "flicker": None,
        "images": [],
    }


def table(n, out, full=False):
    rng = random.Random(34)
    extra_rng = random.Random(35)  # its own: `full` rows time and err as the plain ones
    rows = []
    # Up to 30,000 distinct variants (points of the default space, so the seed pairs match as in a real
    # sweep), each on as many views as the rows need.
    views = [f"view{k:03d}" for k in range(max(3, -(-n // 30000)))]
    variants = -(-n // len(views))
    stride = 7919  # prime to 40,320: consecutive variants spread over the space
    for i in range(variants):
        axes = axes_of(i * stride % SPACE)
        key = key_of(axes)
        if i == 0:
            global BASELINE_KEY
            BASELINE_KEY = key
        # Time and error trade off (more work: slower, less error) with scatter, as a sweep's do.
        cost = 1.0 if i == 0 else math.exp(rng.uniform(-0.7, 1.6))
        for view in views:
            if len(rows) == n:
                break
            batch = "all" if i == 0 else f"{view}-batch{(i - 1) // BATCH}"
            ratios = [1.0] * ROUNDS if i == 0 else [round(cost * (1 + rng.gauss(0, 0.02)), 6) for _ in range(ROUNDS)]
            rmse = max(0.005, 0.12 / cost ** 0.7 * math.exp(rng.gauss(0, 0.25)))
            rows.append(row(key, axes, view, batch, ratios, round(rmse, 6), rng))
            if full:
                rows[-1]["static"] = static_cost(cost)
                rows[-1]["error"]["breakdown"] = breakdown(rows[-1]["error"]["rmse"], extra_rng)
    doc = {"schema_version": 1, "meta": {"generated_by": "bench/big_inputs/generate.py", "scenes": [{"scene": SCENE}]},
           "rows": rows}
    Path(out).write_text(json.dumps(doc, indent=1) + "\n")


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    return str(v)


def manifest(n, out):
    rng = random.Random(34)
    # Templates stay relative to the manifest (list checks they exist): write OUT into a copy of shader_src/.
    text = (REPO / "shader_src" / "aovar.toml").read_text()
    extra = []
    # Every rule is about 24+ samples at quarter resolution, which the manifest's own rules already drop, so
    # the variants `list` prints are the default manifest's; each rule adds 2 to 4 more axes, so it matches
    # some point (a rule that matches none is an error) and the walk must test it everywhere.
    names = [a for a in AXES if a not in ("samples", "resolution")]
    for i in range(n):
        fields = [f"samples = {rng.choice([24, 32])}", "resolution = 0.25"]
        fields += [f"{a} = {toml_value(rng.choice(AXES[a]))}" for a in rng.sample(names, rng.randint(2, 4))]
        extra.append(f"[[rules]]\nskip = {{ {', '.join(fields)} }}\nreason = \"generated rule {i}\"\n")
    Path(out).write_text(text + "\n" + "\n".join(extra))


if __name__ == "__main__":
    full = sys.argv[4:] == ["full"] and sys.argv[1] == "table"
    if len(sys.argv) != 4 + full or sys.argv[1] not in ("table", "manifest") or not sys.argv[2].isdigit():
        sys.exit(__doc__)
    if full:
        table(int(sys.argv[2]), sys.argv[3], full=True)
    else:
        (table if sys.argv[1] == "table" else manifest)(int(sys.argv[2]), sys.argv[3])
