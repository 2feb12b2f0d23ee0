#!/usr/bin/env python3
"""Judges the runs of tests/load/load.sh: each live run beside a CPU hog against the replays of
its own log. Checks per run: the goal reached without collision, perception's MOTA and the
planner's success (the share of its planning cycles that give a trajectory to follow: status
"ok" or "goal reached", against "stop" and "invalid") at most --max-drop points below the
replay's. Prints a table and `load: PASSED` or `FAILED`, writes the figures as JSON, exits 0
when every check passes and 1 otherwise (2 when a run's files are missing)."""
import argparse
import json
import os
import statistics
import sys


def read_json(path):
    with open(path) as f:
        return json.load(f)


def planner_success(path):
    """(success %, cycles) from a "ok stop goal invalid" line; (None, 0) without cycles."""
    with open(path) as f:
        ok, stop, goal, invalid = (int(v) for v in f.read().split())
    total = ok + stop + goal + invalid
    return (100.0 * (ok + goal) / total if total else None), total


def read_run(d):
    summary = read_json(os.path.join(d, "logs", "summary.json"))
    live = read_json(os.path.join(d, "mot_live.json"))
    replay = read_json(os.path.join(d, "mot_replay.json"))
    ps_live, n_live = planner_success(os.path.join(d, "plan_live.txt"))
    ps_replay, n_replay = planner_success(os.path.join(d, "plan_replay.txt"))
    return {
        "success": bool(summary.get("success")), "collisions": int(summary.get("collisions", 0)),
        "goals_reached": summary.get("goals_reached"), "laps": summary.get("laps", 0),
        "time_to_goals_s": summary.get("time_to_goals_s"),
        "mota_live": 100.0 * live["mota"], "mota_replay": 100.0 * replay["mota"],
        "frames_live": live.get("log_frames_evaluated"), "frames_replay": replay.get("log_frames_evaluated"),
        "planner_success_live": ps_live, "planner_success_replay": ps_replay,
        "planner_cycles_live": n_live, "planner_cycles_replay": n_replay,
        "cpu_percent": summary.get("cpu_percent", {}),
    }


def judge(runs, max_drop):
    """Returns a list of (ok, text)."""
    checks = []
    for i, r in enumerate(runs, 1):
        checks.append((r["success"] and r["collisions"] == 0,
                       f"run {i}: goals reached without collision ({r['goals_reached']} goals, {r['laps']} laps, "
                       f"{r['collisions']} collisions)"))
        drop = r["mota_replay"] - r["mota_live"]
        checks.append((drop <= max_drop, f"run {i}: MOTA {r['mota_live']:.1f} % live against {r['mota_replay']:.1f} % "
                                         f"replayed ({drop:+.1f} points lost; at most {max_drop:g})"))
        if r["planner_success_live"] is None or r["planner_success_replay"] is None:
            checks.append((False, f"run {i}: no planning cycle in the live log or the replay"))
            continue
        drop = r["planner_success_replay"] - r["planner_success_live"]
        checks.append((drop <= max_drop,
                       f"run {i}: planner success {r['planner_success_live']:.1f} % of {r['planner_cycles_live']} "
                       f"cycles live against {r['planner_success_replay']:.1f} % of {r['planner_cycles_replay']} "
                       f"replayed ({drop:+.1f} points lost; at most {max_drop:g})"))
    return checks


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dir", required=True, help="load.sh's output folder (run_1, run_2, ...)")
    ap.add_argument("--runs", type=int, required=True)
    ap.add_argument("--workers", type=int, default=0, help="stress-ng workers used (reported)")
    ap.add_argument("--scenario", default="", help="scenario used (reported)")
    ap.add_argument("--max-drop", type=float, default=3.0)
    ap.add_argument("--json", help="write the figures here")
    a = ap.parse_args(argv)
    runs = []
    for i in range(1, a.runs + 1):
        d = os.path.join(a.dir, f"run_{i}")
        try:
            runs.append(read_run(d))
        except (OSError, ValueError, KeyError) as e:
            print(f"load: run {i}: cannot read its results in {d}: {e}", file=sys.stderr)
            return 2
    print(f"{'run':>3} {'goal':>5} {'coll':>4} {'MOTA live':>9} {'replay':>7} {'plan live':>9} {'replay':>7}")
    for i, r in enumerate(runs, 1):
        pl = r["planner_success_live"]
        pr = r["planner_success_replay"]
        print(f"{i:>3} {'yes' if r['success'] else 'no':>5} {r['collisions']:>4} {r['mota_live']:>8.1f}% "
              f"{r['mota_replay']:>6.1f}% {(pl if pl is not None else float('nan')):>8.1f}% "
              f"{(pr if pr is not None else float('nan')):>6.1f}%")
    checks = judge(runs, a.max_drop)
    for ok, text in checks:
        print(("ok:   " if ok else "FAIL: ") + text)
    passed = all(ok for ok, _ in checks)
    figures = {
        "scenario": a.scenario, "workers": a.workers, "max_drop_points": a.max_drop, "runs": runs,
        "median_mota_drop": statistics.median(r["mota_replay"] - r["mota_live"] for r in runs),
        "median_planner_success_drop": statistics.median(
            (r["planner_success_replay"] or 0.0) - (r["planner_success_live"] or 0.0) for r in runs),
        "passed": passed,
    }
    print(f"median loss: MOTA {figures['median_mota_drop']:+.1f} points, planner success "
          f"{figures['median_planner_success_drop']:+.1f} points")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(figures, f, indent=1)
    print("load: PASSED" if passed else "load: FAILED")
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
