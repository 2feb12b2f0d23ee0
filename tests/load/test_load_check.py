#!/usr/bin/env python3
"""load_check.py on made-up runs: runs as good as their replays pass; a MOTA or a planner
success more than --max-drop points below the replay's, a collision, a missed goal, a run
without planning cycles and a run with missing files each decide as they should."""
import io
import json
import os
import sys
import tempfile
import unittest
from contextlib import redirect_stdout, redirect_stderr

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import load_check  # noqa: E402


def put(path, text):
    with open(path, "w") as f:
        f.write(text)


def make_run(d, i, mota_live=0.90, mota_replay=0.91, plan_live="90 5 5 0", plan_replay="92 3 5 0",
             success=True, collisions=0):
    r = os.path.join(d, f"run_{i}")
    os.makedirs(os.path.join(r, "logs"))
    put(os.path.join(r, "logs", "summary.json"),
        json.dumps({"success": success, "collisions": collisions, "goals_reached": 3 if success else 2,
                    "laps": 1, "time_to_goals_s": 40.0}))
    put(os.path.join(r, "mot_live.json"), json.dumps({"mota": mota_live, "log_frames_evaluated": 400}))
    put(os.path.join(r, "mot_replay.json"), json.dumps({"mota": mota_replay, "log_frames_evaluated": 410}))
    put(os.path.join(r, "plan_live.txt"), plan_live + "\n")
    put(os.path.join(r, "plan_replay.txt"), plan_replay + "\n")


class LoadCheck(unittest.TestCase):
    def check(self, runs, max_drop=3.0):
        d = tempfile.mkdtemp()
        for i, kw in enumerate(runs, 1):
            make_run(d, i, **kw)
        out, err = io.StringIO(), io.StringIO()
        with redirect_stdout(out), redirect_stderr(err):
            rc = load_check.main(["--dir", d, "--runs", str(len(runs)), "--max-drop", str(max_drop),
                                  "--json", os.path.join(d, "load.json")])
        figures = None
        if os.path.exists(os.path.join(d, "load.json")):
            with open(os.path.join(d, "load.json")) as f:
                figures = json.load(f)
        return rc, out.getvalue() + err.getvalue(), figures

    def test_runs_as_good_as_their_replays_pass(self):
        rc, text, fig = self.check([{}, {"mota_live": 0.95, "mota_replay": 0.94}])
        self.assertEqual(rc, 0, text)
        self.assertIn("load: PASSED", text)
        # planner success: (90 + 5) / 100 live against (92 + 5) / 100 replayed
        self.assertAlmostEqual(fig["runs"][0]["planner_success_live"], 95.0)
        self.assertAlmostEqual(fig["runs"][0]["planner_success_replay"], 97.0)
        self.assertAlmostEqual(fig["median_mota_drop"], 0.0, places=6)  # +1 and -1 points

    def test_a_mota_lost_beyond_the_limit_fails(self):
        rc, text, fig = self.check([{}, {"mota_live": 0.85, "mota_replay": 0.885}])
        self.assertEqual(rc, 1, text)
        self.assertIn("FAIL: run 2: MOTA 85.0 % live against 88.5 % replayed (+3.5 points lost", text)
        self.assertFalse(fig["passed"])

    def test_a_planner_success_lost_beyond_the_limit_fails(self):
        rc, text, _ = self.check([{"plan_live": "80 15 5 0", "plan_replay": "90 5 5 0"}])
        self.assertEqual(rc, 1, text)
        self.assertIn("FAIL: run 1: planner success 85.0 %", text)

    def test_a_collision_or_a_missed_goal_fails(self):
        rc, text, _ = self.check([{"collisions": 1}])
        self.assertEqual(rc, 1, text)
        self.assertIn("FAIL: run 1: goals reached without collision", text)
        rc, text, _ = self.check([{"success": False}])
        self.assertEqual(rc, 1, text)

    def test_a_run_without_planning_cycles_fails(self):
        rc, text, _ = self.check([{"plan_live": "0 0 0 0"}])
        self.assertEqual(rc, 1, text)
        self.assertIn("no planning cycle", text)

    def test_missing_files_are_named(self):
        d = tempfile.mkdtemp()
        err = io.StringIO()
        with redirect_stdout(io.StringIO()), redirect_stderr(err):
            rc = load_check.main(["--dir", d, "--runs", "1"])
        self.assertEqual(rc, 2)
        self.assertIn("run 1: cannot read its results", err.getvalue())


if __name__ == "__main__":
    unittest.main()
