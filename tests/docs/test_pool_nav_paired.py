#!/usr/bin/env python3
"""Checks scripts/pool-nav-paired.py: pooled counts, intervals and McNemar's p, and its refusals."""
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "pool-nav-paired.py")
spec = importlib.util.spec_from_file_location("pool", SCRIPT)
pool = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pool)


def run_json(seed_base, seeds, rows, reference="sector", growth=None, with_range=True):
    d = {"results": [], "check_growth": growth,
         "paired": {"reference": reference, "results": [
             {"n_dynamic": nd, "planner_model": m, "runs": n, "success_rate": ok / n,
              "reference_success_rate": ref_ok / n, "only_reference": b, "only_model": c,
              "collisions_mover": n - ok, "reference_collisions_mover": n - ref_ok}
             for nd, m, n, ok, ref_ok, b, c in rows]}}
    if with_range:
        d["seed_base"], d["seeds"] = seed_base, seeds
    else:
        d["provenance"] = {"command": f"ucon-bench-nav --seeds {seeds} --seed-base {seed_base}"}
    return d


class PoolTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def write(self, name, d):
        p = os.path.join(self.dir.name, name)
        with open(p, "w") as f:
            json.dump(d, f)
        return p

    def call(self, *paths):
        out = os.path.join(self.dir.name, "out.json")
        r = subprocess.run([sys.executable, SCRIPT, *paths, "--json", out], capture_output=True, text=True)
        if r.returncode != 0:
            return r, None
        with open(out) as f:
            return r, json.load(f)

    def test_formulas(self):
        lo, hi = pool.wilson(100, 120)  # by hand: centre 0.8230, half-width 0.0664
        self.assertAlmostEqual(lo, 0.7565, places=4)
        self.assertAlmostEqual(hi, 0.8894, places=4)
        self.assertEqual(pool.mcnemar_exact(14, 13), 1.0)
        self.assertAlmostEqual(pool.mcnemar_exact(20, 15), 0.4996, places=4)
        self.assertAlmostEqual(pool.mcnemar_exact(0, 6), 2 / 64)
        diff, lo, hi = pool.paired_difference(15, 20, 120)  # b: only the model
        self.assertAlmostEqual(diff, -5 / 120)
        self.assertAlmostEqual(hi - diff, 1.96 * (35 - 25 / 120) ** 0.5 / 120)

    def test_pools_disjoint_ranges(self):
        a = self.write("a.json", run_json(1, 60, [(110, "fapp", 60, 51, 53, 8, 6)]))
        b = self.write("b.json", run_json(61, 60, [(110, "fapp", 60, 44, 47, 12, 9)], with_range=False))
        r, out = self.call(a, b)
        self.assertEqual(r.returncode, 0, r.stderr)
        row = out["results"][0]
        self.assertEqual((row["runs"], row["only_reference"], row["only_model"]), (120, 20, 15))
        self.assertAlmostEqual(row["success_rate"], 95 / 120)
        self.assertAlmostEqual(row["reference_success_rate"], 100 / 120)
        self.assertAlmostEqual(row["mcnemar_exact_p"], pool.mcnemar_exact(20, 15))
        # Seeds for +/-3 points at 35 discordant of 120 and a -5/120 difference.
        d = -5 / 120
        self.assertEqual(row["seeds_to_resolve"], int(-(-(1.96 ** 2) * (35 / 120 - d * d) // 0.03 ** 2)))
        self.assertEqual([(i["seed_base"], i["seeds"]) for i in out["inputs"]], [(1, 60), (61, 60)])

    def test_refusals(self):
        a = self.write("a.json", run_json(1, 60, [(110, "fapp", 60, 51, 53, 8, 6)]))
        overlap = self.write("o.json", run_json(50, 20, [(110, "fapp", 20, 15, 16, 2, 1)]))
        other_ref = self.write("r.json", run_json(61, 60, [(110, "fapp", 60, 51, 53, 8, 6)], reference="fapp"))
        other_model = self.write("m.json", run_json(61, 60, [(110, "no_uncertainty", 60, 51, 53, 8, 6)]))
        other_growth = self.write("g.json", run_json(61, 60, [(110, "fapp", 60, 51, 53, 8, 6)], growth=0.0))
        single = self.write("s.json", {"results": []})
        broken = os.path.join(self.dir.name, "broken.json")
        with open(broken, "w") as f:
            f.write("{\"results\": [")
        for other in (overlap, other_ref, other_model, other_growth, single, broken):
            r, _ = self.call(a, other)
            self.assertEqual(r.returncode, 2, other)
            self.assertIn("pool-nav-paired:", r.stderr)


if __name__ == "__main__":
    unittest.main()
