#!/usr/bin/env python3
"""Judges a soak run (tests/soak/soak.sh): per-process resident memory after the warm-up, the
logger's loss counters, restarts and early exits, collisions. Memory growth is the level held
at the end (the median of the last --level-window-s of samples) against the level after the
warm-up (the median of the first window after it): a burst that is handed back is not growth,
and the peak is reported beside it. Prints a table and a verdict,
writes the figures as JSON, exits 0 when every check passes and 1 otherwise."""
import argparse
import csv
import json
import re
import sys
from collections import defaultdict

# Logger counters that mean a message was lost: on the bus (gaps in a sender's seq field), in
# the logger's queue, or for want of disk.
LOSS_COUNTERS = ("seq_gaps", "dropped_queue_full", "dropped_disk_low", "io_errors")


def read_rss(path):
    """{process: [(t_s, rss_kb, restarts)]} from the CSV; rows with rss -1 (not running) kept out."""
    series = defaultdict(list)
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            rss = int(row["rss_kb"])
            if rss < 0:
                continue
            series[row["process"]].append((float(row["t_s"]), rss, int(row["restarts"])))
    return series


def last_counters(path):
    """Counters of the last message in `ucon-logdump --channel LOGGER_STATUS` output, or None."""
    try:
        text = open(path).read()
    except OSError:
        return None
    blocks = re.split(r"^#\d+ ", text, flags=re.M)
    for block in reversed(blocks):
        names = dict(re.findall(r'^\s*counter_names\[(\d+)\] = "?([^"\n]*)"?$', block, flags=re.M))
        values = dict(re.findall(r"^\s*counter_values\[(\d+)\] = (-?\d+)$", block, flags=re.M))
        if names:
            return {names[i]: int(values[i]) for i in names if i in values}
    return None


def median(values):
    v = sorted(values)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def judge(series, warmup_s, max_growth_pct, counters, summary, exited, stop_reason, window_s=60.0):
    """Returns (checks, per-process figures); each check is (ok, text)."""
    checks, procs = [], {}
    for name, samples in sorted(series.items()):
        first = [s for s in samples if s[0] <= warmup_s]
        after = [s for s in samples if s[0] >= warmup_s]
        fig = {"samples": len(samples), "rss_kb_first": samples[0][1], "rss_kb_end": samples[-1][1],
               "rss_kb_max": max(s[1] for s in samples), "restarts": max(s[2] for s in samples)}
        if after:
            t0, t_end = after[0][0], samples[-1][0]
            base = median([s[1] for s in after if s[0] < t0 + window_s] or [after[0][1]])
            held = median([s[1] for s in after if s[0] >= t_end - window_s] or [after[-1][1]])
            peak = max(s[1] for s in after)
            # Not judged, for the diagnosis: memory that fills up (a map of the same room)
            # levels off, a leak keeps the pace of the first half in the second.
            mid = next(s for s in samples if s[0] >= (t0 + t_end) / 2)
            fig.update({"rss_kb_at_warmup": base, "rss_kb_held_at_end": held, "rss_kb_max_after_warmup": peak,
                        "growth_pct_held": 100.0 * (held - base) / base,
                        "growth_pct_max": 100.0 * (peak - base) / base,
                        "growth_pct_second_half": 100.0 * (samples[-1][1] - mid[1]) / mid[1]})
            checks.append((fig["growth_pct_held"] <= max_growth_pct,
                           f"{name}: RSS {base:.0f} kB after the warm-up, {held:.0f} kB held at the end "
                           f"(+{fig['growth_pct_held']:.1f} % <= {max_growth_pct:g} %; peak {peak} kB, "
                           f"+{fig['growth_pct_max']:.1f} %)"))
        else:
            checks.append((False, f"{name}: no memory sample after the warm-up ({warmup_s:g} s)"))
        checks.append((fig["restarts"] == 0, f"{name}: restarts {fig['restarts']} == 0"))
        procs[name] = fig
    if not series:
        checks.append((False, "memory samples: none"))
    early = [p for p in exited if p != "mission"]
    checks.append((not early, "no process exited before the end" + (f" (exited: {' '.join(early)})" if early else "")))
    if counters is None:
        checks.append((False, "the logger's counters (LOGGER_STATUS) were found in the log"))
    else:
        for c in LOSS_COUNTERS:
            checks.append((counters.get(c, 0) == 0, f"logger {c} {counters.get(c, 0)} == 0"))
    if summary is None:
        checks.append((False, "the mission's summary (summary.json) was found"))
    else:
        checks.append((summary.get("collisions", -1) == 0, f"collisions {summary.get('collisions')} == 0"))
        checks.append((summary.get("laps", 0) >= 1, f"laps {summary.get('laps')} >= 1"))
        checks.append((summary.get("end_reason") == "duration reached",
                       f"the mission ran to its duration (end: {summary.get('end_reason')})"))
    checks.append((stop_reason.startswith("mission finished"), f"the run ended with the mission ({stop_reason or 'unknown'})"))
    return checks, procs


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--summary", required=True, help="the mission's summary.json")
    ap.add_argument("--logger-status", required=True, help="ucon-logdump output of LOGGER_STATUS")
    ap.add_argument("--stop-reason", default="")
    ap.add_argument("--exited-before-end", default="", help="processes that exited during the run")
    ap.add_argument("--warmup-s", type=float, default=60.0)
    ap.add_argument("--max-growth-pct", type=float, default=5.0)
    ap.add_argument("--level-window-s", type=float, default=60.0,
                    help="memory level = median of the samples in this window after the warm-up / at the end")
    ap.add_argument("--wall-s", type=float, default=float("nan"))
    ap.add_argument("--minutes", type=float, default=float("nan"))
    ap.add_argument("--scenario", default="")
    ap.add_argument("--json", required=True)
    a = ap.parse_args(argv)

    series = read_rss(a.csv)
    try:
        summary = json.load(open(a.summary))
    except (OSError, ValueError):
        summary = None
    counters = last_counters(a.logger_status)
    checks, procs = judge(series, a.warmup_s, a.max_growth_pct, counters, summary,
                          a.exited_before_end.split(), a.stop_reason, window_s=a.level_window_s)
    ok = all(c[0] for c in checks)

    print(f"{'process':<16} {'RSS@warm-up':>12} {'held@end':>10} {'max after':>10} {'growth':>8} "
          f"{'peak':>8} {'2nd half':>8} {'restarts':>8}")
    for name, f in procs.items():
        print(f"{name:<16} {f.get('rss_kb_at_warmup', -1):>9.0f} kB {f.get('rss_kb_held_at_end', -1):>7.0f} kB "
              f"{f.get('rss_kb_max_after_warmup', -1):>7} kB {f.get('growth_pct_held', float('nan')):>+7.1f}% "
              f"{f.get('growth_pct_max', float('nan')):>+7.1f}% "
              f"{f.get('growth_pct_second_half', float('nan')):>+7.1f}% {f['restarts']:>8}")
    for good, text in checks:
        print(("ok:   " if good else "FAIL: ") + text)
    print("soak: " + ("PASSED" if ok else "FAILED"))
    result = {"passed": ok, "scenario": a.scenario, "minutes": a.minutes, "wall_s": a.wall_s,
              "warmup_s": a.warmup_s, "max_growth_pct": a.max_growth_pct, "processes": procs,
              "logger_counters": {c: (counters or {}).get(c) for c in LOSS_COUNTERS},
              "logger_messages": (counters or {}).get("messages"),
              "mission": summary, "stop_reason": a.stop_reason,
              "checks": [{"ok": g, "check": t} for g, t in checks]}
    with open(a.json, "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
