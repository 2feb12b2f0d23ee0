#!/usr/bin/env python3
"""soak_check.py on made-up runs: a clean one passes; memory growth over the limit after the
warm-up, growth within the warm-up, a restart, an early exit, lost messages, a collision and
a missing logger status each decide as they should."""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import soak_check  # noqa: E402

def logger_status(event, messages, gaps):
    """One LOGGER_STATUS message as ucon-logdump prints it."""
    counters = [("messages", messages), ("seq_gaps", gaps), ("dropped_queue_full", 0)]
    lines = [f"#{event} t={event} LOGGER_STATUS ucon.process_status_t", f"  num_counters = {len(counters)}"]
    lines += [f'  counter_names[{i}] = "{n}"' for i, (n, _) in enumerate(counters)]
    lines += [f"  counter_values[{i}] = {v}" for i, (_, v) in enumerate(counters)]
    return "\n".join(lines) + "\n"


class SoakCheck(unittest.TestCase):
    def run_check(self, rss=None, gaps=0, summary=None, exited="mission", restarts=0, status=True):
        d = tempfile.mkdtemp()
        rss = rss or {"planner": [1000, 1200, 1200, 1210, 1220], "logger": [500, 500, 505, 510, 500]}
        with open(f"{d}/rss.csv", "w") as f:
            f.write("t_s,process,pid,rss_kb,restarts\n")
            for name, values in rss.items():
                for i, v in enumerate(values):
                    # samples at 0, 30, 60, 90, 120 s; the last restarts count applies at the end
                    r = restarts if i == len(values) - 1 else 0
                    f.write(f"{30 * i},{name},42,{v},{r}\n")
                f.write(f"150,{name},42,-1,0\n")  # stopped: not a sample
        if status:
            with open(f"{d}/status.txt", "w") as f:
                f.write(logger_status(10, 500, 0) + logger_status(11, 900, gaps))
        s = summary or {"end_reason": "duration reached", "success": True, "collisions": 0, "laps": 3}
        with open(f"{d}/summary.json", "w") as f:
            json.dump(s, f)
        rc = soak_check.main(["--csv", f"{d}/rss.csv", "--summary", f"{d}/summary.json",
                              "--logger-status", f"{d}/status.txt", "--exited-before-end", exited,
                              "--stop-reason", "mission finished (status 0)", "--warmup-s", "60",
                              "--max-growth-pct", "5", "--level-window-s", "30", "--json", f"{d}/soak.json"])
        with open(f"{d}/soak.json") as f:
            return rc, json.load(f)

    def test_given_a_clean_run_then_it_passes_with_growth_measured_from_the_warm_up(self):
        rc, j = self.run_check()
        self.assertEqual(rc, 0)
        self.assertTrue(j["passed"])
        # planner: 1200 kB at 60 s (the 30-s window after the warm-up), held at the end (samples
        # after 90 s: 1210, 1220) 1215 kB: +1.25 %; the first minute's +20 % does not count
        self.assertAlmostEqual(j["processes"]["planner"]["growth_pct_held"], 100 * 15 / 1200, places=6)
        self.assertAlmostEqual(j["processes"]["planner"]["growth_pct_max"], 100 * 20 / 1200, places=6)
        self.assertEqual(j["processes"]["planner"]["samples"], 5)
        # second half: from the sample at (60 + 120) / 2 = 90 s (1210 kB) to the end (1220 kB)
        self.assertAlmostEqual(j["processes"]["planner"]["growth_pct_second_half"], 100 * 10 / 1210, places=6)
        self.assertEqual(j["logger_messages"], 900, "the last LOGGER_STATUS counts")

    def test_given_growth_over_the_limit_after_the_warm_up_then_it_fails(self):
        rc, j = self.run_check(rss={"perception": [1000, 1000, 1000, 1050, 1061]})
        self.assertEqual(rc, 1)
        self.assertAlmostEqual(j["processes"]["perception"]["growth_pct_held"], 5.55, places=6)

    def test_given_growth_at_the_limit_then_it_passes(self):
        rc, _ = self.run_check(rss={"perception": [1000, 1000, 1000, 1040, 1060]})
        self.assertEqual(rc, 0)

    def test_given_a_burst_handed_back_then_it_is_reported_not_judged(self):
        # A peak of +30 % at 120 s, back to the warm-up level by the end (samples every 30 s).
        rc, j = self.run_check(rss={"logger": [900, 1000, 1000, 1000, 1300, 1000, 1000, 1000, 1000]})
        self.assertEqual(rc, 0)
        self.assertAlmostEqual(j["processes"]["logger"]["growth_pct_max"], 30.0, places=6)
        self.assertAlmostEqual(j["processes"]["logger"]["growth_pct_held"], 0.0, places=6)

    def test_given_a_level_that_keeps_rising_then_it_fails_even_without_a_peak(self):
        rc, j = self.run_check(rss={"odometry": [1000, 1000, 1000, 1020, 1040, 1060, 1080]})
        self.assertEqual(rc, 1)

    def test_given_a_restart_then_it_fails(self):
        self.assertEqual(self.run_check(restarts=1)[0], 1)

    def test_given_a_process_that_exited_before_the_end_then_it_fails(self):
        self.assertEqual(self.run_check(exited="mission odometry")[0], 1)

    def test_given_messages_lost_on_the_bus_then_it_fails(self):
        rc, j = self.run_check(gaps=3)
        self.assertEqual(rc, 1)
        self.assertEqual(j["logger_counters"]["seq_gaps"], 3, "the last status, not the first")

    def test_given_a_collision_then_it_fails(self):
        s = {"end_reason": "duration reached", "success": False, "collisions": 1, "laps": 3}
        self.assertEqual(self.run_check(summary=s)[0], 1)

    def test_given_no_logger_status_then_it_fails(self):
        self.assertEqual(self.run_check(status=False)[0], 1)


if __name__ == "__main__":
    unittest.main()
