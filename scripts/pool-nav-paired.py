#!/usr/bin/env python3
"""Pools the paired comparisons of several `ucon-bench-nav --planner-model A,B,...` runs.

    scripts/pool-nav-paired.py RUN.json [RUN.json ...] [--json OUT.json] [--resolve 0.03]

Each input is the JSON of one `ucon-bench-nav` run with several planner models (its "paired"
section), on seeds disjoint from the other inputs' and with the same density, models and
reference. McNemar's test and the paired difference need only the discordant counts, so pooling
disjoint seed ranges is exact: the successes, the seeds only the reference succeeded on and the
seeds only the other model succeeded on add up. Printed and written per density and model:
success with its Wilson 95 % interval, the difference to the reference with its 95 % Wald
interval (the formulas of tests/bench/planning/paired_stats.cpp), McNemar's exact p, and the
number of seeds at which, at the pooled discordance, that interval would be +/- --resolve wide
(1.96^2 (d - diff^2) / resolve^2, d = discordant pairs per seed).

The seed range of an input is its "seed_base" and "seeds", or, in files written before those
fields, the --seed-base and --seeds of its provenance command (seed base 1 when absent).
"""
import argparse
import json
import math
import re
import sys


Z = 1.96  # the 95 % normal quantile, as paired_stats.cpp uses it


class BadInput(Exception):
    pass


def wilson(k, n):
    if n <= 0:
        return (math.nan, math.nan)
    p = k / n
    den = 1 + Z * Z / n
    centre = (p + Z * Z / (2 * n)) / den
    half = Z * math.sqrt(p * (1 - p) / n + Z * Z / (4 * n * n)) / den
    return (centre - half, centre + half)


def paired_difference(b, c, n):
    """(b - c) / n and its 95 % Wald interval; b: seeds only the model succeeded on."""
    if n <= 0:
        return (math.nan, math.nan, math.nan)
    diff = (b - c) / n
    half = Z * math.sqrt(max(0.0, b + c - (b - c) ** 2 / n)) / n
    return (diff, diff - half, diff + half)


def mcnemar_exact(b, c):
    m = b + c
    if m == 0:
        return 1.0
    k = min(b, c)
    tail = sum(math.comb(m, i) for i in range(k + 1)) / 2.0 ** m
    return min(1.0, 2.0 * tail)


def seed_range(run, path):
    if "seed_base" in run and "seeds" in run:
        return int(run["seed_base"]), int(run["seeds"])
    cmd = run.get("provenance", {}).get("command", "")
    m_n = re.search(r"--seeds[ =](\d+)", cmd)
    if not m_n:
        raise BadInput(f"{path}: no seed range (neither seed_base/seeds nor --seeds in its provenance command)")
    m_b = re.search(r"--seed-base[ =](\d+)", cmd)
    return (int(m_b.group(1)) if m_b else 1), int(m_n.group(1))


def load(path):
    try:
        with open(path) as f:
            run = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        raise BadInput(f"{path}: {e}")
    if "paired" not in run or "results" not in run["paired"]:
        raise BadInput(f"{path}: no \"paired\" section (a run with one planner model?)")
    return run


def pool(paths):
    runs = [(p, load(p)) for p in paths]
    reference = {r["paired"]["reference"] for _, r in runs}
    if len(reference) != 1:
        raise BadInput(f"the inputs have different reference models: {sorted(reference)}")
    growth = {json.dumps(r.get("check_growth")) for _, r in runs}
    if len(growth) != 1:
        raise BadInput(f"the inputs have different --check-growth: {sorted(growth)}")
    ranges = []
    for p, r in runs:
        b, n = seed_range(r, p)
        for q, b2, n2 in ranges:
            if b < b2 + n2 and b2 < b + n:
                raise BadInput(f"{p} (seeds {b}-{b + n - 1}) overlaps {q} (seeds {b2}-{b2 + n2 - 1})")
        ranges.append((p, b, n))
    cells = {}  # (n_dynamic, model) -> sums
    keys = None
    for p, r in runs:
        k = sorted((x["n_dynamic"], x["planner_model"]) for x in r["paired"]["results"])
        if keys is not None and k != keys:
            raise BadInput(f"{p}: densities or models differ from the first input's")
        keys = k
        for x in r["paired"]["results"]:
            n = int(x["runs"])
            c = cells.setdefault((x["n_dynamic"], x["planner_model"]),
                                 {"runs": 0, "ok": 0, "ref_ok": 0, "only_ref": 0, "only_model": 0,
                                  "coll_mover": 0, "ref_coll_mover": 0})
            c["runs"] += n
            c["ok"] += round(x["success_rate"] * n)
            c["ref_ok"] += round(x["reference_success_rate"] * n)
            c["only_ref"] += int(x["only_reference"])
            c["only_model"] += int(x["only_model"])
            c["coll_mover"] += int(x.get("collisions_mover", 0))
            c["ref_coll_mover"] += int(x.get("reference_collisions_mover", 0))
    return reference.pop(), ranges, runs, cells


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("inputs", nargs="+", help="ucon-bench-nav JSON files with a paired section")
    ap.add_argument("--json", help="write the pooled figures to this file")
    ap.add_argument("--resolve", type=float, default=0.03,
                    help="half-width of the difference's interval to size the seed count for (default 0.03)")
    a = ap.parse_args()
    if not a.resolve > 0:
        print("pool-nav-paired: --resolve must be positive", file=sys.stderr)
        return 2
    try:
        reference, ranges, runs, cells = pool(a.inputs)
    except BadInput as e:
        print(f"pool-nav-paired: {e}", file=sys.stderr)
        return 2
    except (KeyError, TypeError, ValueError, AttributeError) as e:
        print(f"pool-nav-paired: an input is not a ucon-bench-nav JSON ({type(e).__name__}: {e})", file=sys.stderr)
        return 2
    rows = []
    for (nd, model), c in sorted(cells.items()):
        n = c["runs"]
        diff, lo, hi = paired_difference(c["only_model"], c["only_ref"], n)
        disc = (c["only_model"] + c["only_ref"]) / n if n else math.nan
        need = math.ceil(Z * Z * max(0.0, disc - diff * diff) / a.resolve ** 2) if n else None
        rows.append({
            "n_dynamic": nd, "planner_model": model, "runs": n,
            "reference_success_rate": c["ref_ok"] / n, "reference_ci95": list(wilson(c["ref_ok"], n)),
            "success_rate": c["ok"] / n, "success_ci95": list(wilson(c["ok"], n)),
            "only_reference": c["only_ref"], "only_model": c["only_model"],
            "difference": diff, "difference_ci95": [lo, hi],
            "mcnemar_exact_p": mcnemar_exact(c["only_ref"], c["only_model"]),
            "discordant_per_seed": disc, "seeds_to_resolve": need,
            "collisions_mover": c["coll_mover"], "reference_collisions_mover": c["ref_coll_mover"],
        })
    seeds = sorted((b, n) for _, b, n in ranges)
    print(f"Pooled against {reference} over {sum(n for _, n in seeds)} seeds "
          f"({', '.join(f'{b}-{b + n - 1}' for b, n in seeds)}), {len(runs)} runs of ucon-bench-nav")
    print(f"{'N_d':>4} {'model':>15} {'seeds':>6} | {'reference [%]':>22} {'model [%]':>22} | "
          f"{'only_r':>6} {'only_m':>6} | {'diff [points]':>23} {'p':>6} | seeds for +/-{a.resolve * 100:g}")
    for r in rows:
        print(f"{r['n_dynamic']:>4} {r['planner_model']:>15} {r['runs']:>6} | "
              f"{100 * r['reference_success_rate']:5.1f} [{100 * r['reference_ci95'][0]:5.1f}, {100 * r['reference_ci95'][1]:5.1f}] "
              f"{100 * r['success_rate']:9.1f} [{100 * r['success_ci95'][0]:5.1f}, {100 * r['success_ci95'][1]:5.1f}] | "
              f"{r['only_reference']:>6} {r['only_model']:>6} | "
              f"{100 * r['difference']:+5.1f} [{100 * r['difference_ci95'][0]:+6.1f}, {100 * r['difference_ci95'][1]:+6.1f}] "
              f"{r['mcnemar_exact_p']:6.3f} | {r['seeds_to_resolve']}")
    if a.json:
        out = {
            "reference": reference,
            "inputs": [{"file": p, "seed_base": b, "seeds": n,
                        "git_revision": r.get("provenance", {}).get("git_revision")}
                       for (p, b, n), (_, r) in zip(ranges, runs)],
            "resolve": a.resolve,
            "results": rows,
        }
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
