#include "open_report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "../bench_util.hpp"
#include "paired_stats.hpp"

namespace ucon::bench {

namespace {

std::string num(double x, int prec = 4) {
  if (!std::isfinite(x)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", prec + 2, x);
  return buf;
}

const char* motionName(world::MotionKind k) {
  switch (k) {
    case world::MotionKind::kConstantVelocity: return "CV";
    case world::MotionKind::kConstantAcceleration: return "CA";
    case world::MotionKind::kSinusoidal: return "sinusoidal";
    case world::MotionKind::kPedestrian: return "pedestrian";
  }
  return "?";
}

struct Cell {
  int64_t probes = 0, free = 0, mover_contacts = 0, static_contacts = 0, no_plan = 0, avoidable = 0,
          avoidable_free = 0, passed = 0, passed_free = 0;
  /// Plans the check rejected, by its reason: static, dynamic, limits, other (no result, bad input).
  int64_t rejected[4] = {0, 0, 0, 0};
  double jerk_sum = 0.0;
  int64_t jerk_n = 0;
  std::vector<double> plan_ms, plan_cpu_ms, iterations;
};

/// Neither a contact with a mover nor a missing plan (static contacts set aside).
bool mover_free(const PlanOutcome& o) { return o.has_plan && !o.play.mover_contact; }

struct Count {
  int64_t probes = 0, free = 0;
};

}  // namespace

const char* trackAgeBin(double age_s) {
  if (age_s < 0.0) return "untracked";
  if (age_s < 0.5) return "<0.5 s";
  if (age_s <= 2.0) return "0.5-2 s";
  return ">2 s";
}

bool reportOpenLoop(const std::vector<OpenRunKey>& keys, const std::vector<OpenLoopResult>& runs,
                    const std::vector<std::string>& methods, const std::vector<double>& horizons,
                    const std::vector<int>& densities, const std::string& command, const std::string& settings_json,
                    const std::string& json_path) {
  const std::size_t nm = methods.size();
  std::ostringstream results, paired, by_age, by_motion;
  const char* age_bins[] = {"<0.5 s", "0.5-2 s", ">2 s", "untracked"};
  const world::MotionKind kinds[] = {world::MotionKind::kConstantVelocity, world::MotionKind::kConstantAcceleration,
                                     world::MotionKind::kSinusoidal};
  int64_t total_skipped = 0, reference_collisions = 0, legs = 0;
  for (const auto& r : runs) {
    total_skipped += r.skipped;
    reference_collisions += r.run.collision;
    legs += r.run.goals_reached;
  }
  bool first_result = true, first_pair = true, first_age = true, first_motion = true;
  for (std::size_t h = 0; h < horizons.size(); ++h) {
    std::printf("\n%s\nOpen-loop probes, evaluation horizon %.1f s (dynamic cost and check over the same horizon)\n",
                command.c_str(), horizons[h]);
    std::printf("%-15s %5s | %6s %8s %15s %6s %6s %6s | %9s %9s %19s | %6s %8s %8s %6s\n", "method", "N_d", "probes",
                "free[%]", "95% CI", "mover", "static", "noplan", "avoid[%]", "chk+fr[%]", "rejected s/d/l/o", "E",
                "tp_med", "cpu_p95", "evals");
    for (const int d : densities) {
      std::vector<Cell> cells(nm);
      std::map<std::string, std::vector<Count>> age, motion;
      // Paired outcomes of method 0 (the sector) against every other.
      std::vector<int64_t> b(nm, 0), c(nm, 0), both_free(nm, 0), both_contact(nm, 0);
      // The same on mover contacts alone (static contacts set aside).
      std::vector<int64_t> mb(nm, 0), mc(nm, 0);
      for (std::size_t ri = 0; ri < runs.size(); ++ri) {
        if (keys[ri].n_dynamic != d) continue;
        for (const auto& p : runs[ri].probes) {
          const std::string abin = trackAgeBin(p.nearest_track_age);
          const std::string kbin = motionName(p.nearest_kind);
          auto& av = age[abin];
          auto& kv = motion[kbin];
          av.resize(nm);
          kv.resize(nm);
          for (std::size_t m = 0; m < nm; ++m) {
            const PlanOutcome& o = p.outcomes[h * nm + m];
            Cell& cell = cells[m];
            ++cell.probes;
            cell.free += o.contactFree();
            cell.no_plan += !o.has_plan;
            cell.mover_contacts += o.has_plan && o.play.mover_contact;
            cell.static_contacts += o.has_plan && o.play.static_contact;
            if (o.avoidable()) {
              ++cell.avoidable;
              cell.avoidable_free += o.contactFree();
            }
            cell.passed += o.passed_check;
            if (!o.passed_check) {
              const trajopt::PlanStatus st = o.status;
              ++cell.rejected[st == trajopt::PlanStatus::kStaticCollision    ? 0
                              : st == trajopt::PlanStatus::kDynamicCollision ? 1
                              : st == trajopt::PlanStatus::kLimitViolation   ? 2
                                                                              : 3];
            }
            cell.passed_free += o.passed_check && o.contactFree();
            if (o.has_plan) {
              cell.jerk_sum += o.play.jerk_mean;
              ++cell.jerk_n;
            }
            cell.plan_ms.push_back(o.plan_ms);
            cell.plan_cpu_ms.push_back(o.plan_cpu_ms);
            cell.iterations.push_back(o.iterations);
            ++av[m].probes;
            av[m].free += o.contactFree();
            ++kv[m].probes;
            kv[m].free += o.contactFree();
            if (m > 0) {
              const bool s = p.outcomes[h * nm].contactFree(), x = o.contactFree();
              both_free[m] += s && x;
              const bool sm = mover_free(p.outcomes[h * nm]), xm = mover_free(o);
              mb[m] += sm && !xm;
              mc[m] += !sm && xm;
              both_contact[m] += !s && !x;
              b[m] += s && !x;
              c[m] += !s && x;
            }
          }
        }
      }
      for (std::size_t m = 0; m < nm; ++m) {
        const Cell& cl = cells[m];
        const double rate = cl.probes ? double(cl.free) / double(cl.probes) : NAN;
        const Interval ci = wilson(cl.free, cl.probes);
        const double avoid_rate = cl.avoidable ? double(cl.avoidable_free) / double(cl.avoidable) : NAN;
        const double passed_rate = cl.probes ? double(cl.passed_free) / double(cl.probes) : NAN;
        const double energy = cl.jerk_n ? cl.jerk_sum / double(cl.jerk_n) : NAN;
        char rejected[64];
        std::snprintf(rejected, sizeof(rejected), "%lld/%lld/%lld/%lld", (long long)cl.rejected[0],
                      (long long)cl.rejected[1], (long long)cl.rejected[2], (long long)cl.rejected[3]);
        std::printf("%-15s %5d | %6lld %8.2f  [%5.2f, %5.2f] %6lld %6lld %6lld | %9.2f %9.2f %19s | %6.2f %8.2f %8.2f %6.0f\n",
                    methods[m].c_str(), d, (long long)cl.probes, 100.0 * rate, 100.0 * ci.lo, 100.0 * ci.hi,
                    (long long)cl.mover_contacts, (long long)cl.static_contacts, (long long)cl.no_plan,
                    100.0 * avoid_rate, 100.0 * passed_rate, rejected, energy, percentile(cl.plan_ms, 0.5),
                    percentile(cl.plan_cpu_ms, 0.95), percentile(cl.iterations, 0.5));
        results << (first_result ? "" : ",\n") << "    {\"horizon_s\": " << num(horizons[h]) << ", \"n_dynamic\": " << d
                << ", \"method\": \"" << methods[m] << "\", \"probes\": " << cl.probes
                << ", \"contact_free_rate\": " << num(rate) << ", \"ci95_lo\": " << num(ci.lo)
                << ", \"ci95_hi\": " << num(ci.hi) << ", \"mover_contacts\": " << cl.mover_contacts
                << ", \"static_contacts\": " << cl.static_contacts << ", \"no_plan\": " << cl.no_plan
                << ", \"avoidable_probes\": " << cl.avoidable << ", \"contact_free_avoidable_rate\": " << num(avoid_rate)
                << ", \"mover_contact_free_rate\": " << num(cl.probes ? 1.0 - double(cl.mover_contacts + cl.no_plan) / double(cl.probes) : NAN)
                << ", \"passed_check\": " << cl.passed << ", \"passed_check_contact_free_rate\": " << num(passed_rate)
                << ", \"check_rejected\": {\"static\": " << cl.rejected[0] << ", \"dynamic\": " << cl.rejected[1]
                << ", \"limits\": " << cl.rejected[2] << ", \"other\": " << cl.rejected[3] << "}"
                << ", \"energy_jerk_mean\": " << num(energy)
                << ", \"plan_ms_median\": " << num(percentile(cl.plan_ms, 0.5))
                << ", \"plan_cpu_ms_median\": " << num(percentile(cl.plan_cpu_ms, 0.5))
                << ", \"plan_cpu_ms_p95\": " << num(percentile(cl.plan_cpu_ms, 0.95))
                << ", \"evaluations_median\": " << num(percentile(cl.iterations, 0.5)) << "}";
        first_result = false;
      }
      for (std::size_t m = 1; m < nm; ++m) {
        const McNemar t = mcnemar(b[m], c[m]);
        const int64_t n = cells[m].probes;
        const PairedDifference pd = pairedDifference(b[m], c[m], n);
        const char* verdict = t.exact_p < 0.05 ? (b[m] > c[m] ? "better" : "worse") : "no significant difference";
        const McNemar tm = mcnemar(mb[m], mc[m]);
        const PairedDifference pm = pairedDifference(mb[m], mc[m], n);
        const char* mverdict = tm.exact_p < 0.05 ? (mb[m] > mc[m] ? "better" : "worse") : "no significant difference";
        paired << (first_pair ? "" : ",\n") << "    {\"horizon_s\": " << num(horizons[h]) << ", \"n_dynamic\": " << d
               << ", \"method\": \"" << methods[0] << "\", \"baseline\": \"" << methods[m] << "\", \"pairs\": " << n
               << ", \"both_free\": " << both_free[m] << ", \"only_" << methods[0] << "_free\": " << b[m]
               << ", \"only_baseline_free\": " << c[m] << ", \"both_contact\": " << both_contact[m]
               << ", \"rate_difference\": " << num(pd.diff) << ", \"difference_ci95_lo\": " << num(pd.lo)
               << ", \"difference_ci95_hi\": " << num(pd.hi) << ", \"mcnemar_exact_p\": " << num(t.exact_p)
               << ", \"mcnemar_chi2_cc\": " << num(t.chi2) << ", \"mcnemar_chi2_p\": " << num(t.chi2_p)
               << ", \"verdict\": \"" << verdict << "\", \"movers_only_" << methods[0] << "_free\": " << mb[m]
               << ", \"movers_only_baseline_free\": " << mc[m] << ", \"movers_difference\": " << num(pm.diff)
               << ", \"movers_difference_ci95_lo\": " << num(pm.lo) << ", \"movers_difference_ci95_hi\": " << num(pm.hi)
               << ", \"movers_mcnemar_exact_p\": " << num(tm.exact_p) << ", \"movers_verdict\": \"" << mverdict
               << "\"}";
        first_pair = false;
        std::printf("  paired %s vs %-15s N_d=%3d: both free %lld, only %s %lld, only %s %lld, both contact %lld; "
                    "diff %+.2f %% [%+.2f, %+.2f]; McNemar exact p=%.3g, chi2=%.2f p=%.3g -> %s\n",
                    methods[0].c_str(), methods[m].c_str(), d, (long long)both_free[m], methods[0].c_str(),
                    (long long)b[m], methods[m].c_str(), (long long)c[m], (long long)both_contact[m], 100.0 * pd.diff,
                    100.0 * pd.lo, 100.0 * pd.hi, t.exact_p, t.chi2, t.chi2_p, verdict);
        std::printf("    movers only (static contacts set aside): only %s free %lld, only %s free %lld; diff %+.2f %% "
                    "[%+.2f, %+.2f]; McNemar exact p=%.3g -> %s\n",
                    methods[0].c_str(), (long long)mb[m], methods[m].c_str(), (long long)mc[m], 100.0 * pm.diff,
                    100.0 * pm.lo, 100.0 * pm.hi, tm.exact_p, mverdict);
      }
      auto breakdown = [&](std::map<std::string, std::vector<Count>>& table, const char* key,
                           const std::vector<std::string>& order, std::ostringstream& js, bool& first) {
        for (const auto& bin : order) {
          auto it = table.find(bin);
          if (it == table.end() || it->second.empty()) continue;
          std::printf("  %-10s %-10s N_d=%3d probes %5lld contact-free [%%]:", key, bin.c_str(), d,
                      (long long)it->second[0].probes);
          js << (first ? "" : ",\n") << "    {\"horizon_s\": " << num(horizons[h]) << ", \"n_dynamic\": " << d
             << ", \"" << key << "\": \"" << bin << "\", \"probes\": " << it->second[0].probes;
          for (std::size_t m = 0; m < nm; ++m) {
            const auto& cnt = it->second[m];
            const double r = cnt.probes ? double(cnt.free) / double(cnt.probes) : NAN;
            std::printf(" %s %.2f", methods[m].c_str(), 100.0 * r);
            js << ", \"" << methods[m] << "\": " << num(r);
          }
          std::printf("\n");
          js << "}";
          first = false;
        }
      };
      breakdown(age, "track_age", {age_bins[0], age_bins[1], age_bins[2], age_bins[3]}, by_age, first_age);
      std::vector<std::string> kind_names;
      for (const auto k : kinds) kind_names.push_back(motionName(k));
      breakdown(motion, "motion", kind_names, by_motion, first_motion);
    }
  }
  std::printf("(free: the raw plan touches neither a mover nor a static obstacle within the horizon; avoid: the same "
              "over plans whose first mover contact, if any, was with a tracked mover; chk+fr: passed the optimiser's "
              "check and contact-free; rejected s/d/l/o: plans the check rejected for a static obstacle, a predicted "
              "mover, the limits, or other (no result); E: mean |jerk| of the plans [m/s^3]; tp_med: median planning time [ms]; "
              "cpu_p95: plan thread CPU p95 [ms]; breakdowns by the mover nearest to the robot at plan time)\n");
  std::printf("reference runs: %zu, shuttle legs completed %lld, reference collisions %lld, probe times without a "
              "problem %lld\n",
              runs.size(), (long long)legs, (long long)reference_collisions, (long long)total_skipped);
  if (json_path.empty()) return true;
  std::ofstream js(json_path);
  js << "{\n  \"protocol\": \"open\",\n  \"settings\": {" << settings_json << ", \"reference_runs\": " << runs.size()
     << ", \"shuttle_legs\": " << legs << ", \"reference_collisions\": " << reference_collisions
     << ", \"probe_times_without_problem\": " << total_skipped << "},\n  \"results\": [\n"
     << results.str() << "\n  ],\n  \"paired\": [\n" << paired.str() << "\n  ],\n  \"by_track_age\": [\n"
     << by_age.str() << "\n  ],\n  \"by_motion\": [\n" << by_motion.str() << "\n  ]\n}\n";
  if (!js) {
    std::fprintf(stderr, "ucon-bench-planning: cannot write %s\n", json_path.c_str());
    return false;
  }
  std::printf("wrote %s\n", json_path.c_str());
  return true;
}

}  // namespace ucon::bench
