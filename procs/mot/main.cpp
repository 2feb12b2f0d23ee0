// ucon-mot: CLEAR-MOT evaluation of a run.
//   ucon-mot --log run.lcm [--threshold 1.0] [--json]
//       SIM_GROUND_TRUTH vs PERCEPTION_OBJECTS from an LCM log, x-y distance in metres.
//   ucon-mot --gt gt.txt --pred pred.txt [--iou 0.5] [--json]
//       MOTChallenge text files, boxes matched by IoU.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "ucon/mot/mot_log.hpp"
#include "ucon/mot/mot_challenge.hpp"
#include "ucon/runtime/config_file.hpp"

namespace {

std::string num(double v, int precision = 6) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
  return buf;
}

std::string pct(double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f %%", 100.0 * v);
  return buf;
}

void printJson(const ucon::mot::ClearMotSummary& s, const ucon::mot::LogMatchStats* log) {
  std::cout << "{\"mota\": " << num(s.mota) << ", \"motp\": " << num(s.motp)
            << ", \"fp\": " << s.num_false_positives << ", \"fn\": " << s.num_misses
            << ", \"idsw\": " << s.num_switches << ", \"num_objects\": " << s.num_objects
            << ", \"num_predictions\": " << s.num_predictions << ", \"num_matches\": " << s.num_matches
            << ", \"num_frames\": " << s.num_frames << ", \"recall\": " << num(s.recall)
            << ", \"precision\": " << num(s.precision) << ", \"fn_rate\": " << num(s.fn_rate)
            << ", \"fp_rate\": " << num(s.fp_rate) << ", \"mismatch_rate\": " << num(s.mismatch_rate)
            << ", \"num_unique_objects\": " << s.num_unique_objects
            << ", \"mostly_tracked\": " << s.mostly_tracked
            << ", \"partially_tracked\": " << s.partially_tracked
            << ", \"mostly_lost\": " << s.mostly_lost
            << ", \"num_fragmentations\": " << s.num_fragmentations;
  if (log) {
    std::cout << ", \"log_frames_evaluated\": " << log->frames_evaluated
              << ", \"log_frames_without_ground_truth\": " << log->frames_without_ground_truth
              << ", \"log_invalid_frames\": " << log->invalid_frames
              << ", \"log_undecodable_messages\": " << log->undecodable_messages;
  }
  std::cout << "}\n";
}

void printTable(const ucon::mot::ClearMotSummary& s, const std::string& distance_unit) {
  std::printf("%-22s %s\n", "MOTA", pct(s.mota).c_str());
  std::printf("%-22s %s %s\n", "MOTP", num(s.motp, 4).c_str(), distance_unit.c_str());
  std::printf("%-22s %lld\n", "identity switches", static_cast<long long>(s.num_switches));
  std::printf("%-22s %lld (%s)\n", "false negatives", static_cast<long long>(s.num_misses), pct(s.fn_rate).c_str());
  std::printf("%-22s %lld (%s)\n", "false positives", static_cast<long long>(s.num_false_positives),
              pct(s.fp_rate).c_str());
  std::printf("%-22s %s\n", "mismatch rate", pct(s.mismatch_rate).c_str());
  std::printf("%-22s %s\n", "recall", pct(s.recall).c_str());
  std::printf("%-22s %s\n", "precision", pct(s.precision).c_str());
  std::printf("%-22s %lld\n", "objects (occurrences)", static_cast<long long>(s.num_objects));
  std::printf("%-22s %lld\n", "predictions", static_cast<long long>(s.num_predictions));
  std::printf("%-22s %lld\n", "frames", static_cast<long long>(s.num_frames));
  std::printf("%-22s %lld / %lld / %lld of %lld\n", "MT / PT / ML", static_cast<long long>(s.mostly_tracked),
              static_cast<long long>(s.partially_tracked), static_cast<long long>(s.mostly_lost),
              static_cast<long long>(s.num_unique_objects));
  std::printf("%-22s %lld\n", "fragmentations", static_cast<long long>(s.num_fragmentations));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"CLEAR-MOT evaluation (MOTA, MOTP, IDSW, ...) of a UCON run or MOTChallenge files."};
  std::string log_path, gt_path, pred_path;
  ucon::mot::LogEvalOptions opt;
  bool allow_truncated = false;
  double iou = 0.5;
  bool json = false;
  auto* log_opt = app.add_option("--log", log_path, "LCM log with SIM_GROUND_TRUTH and PERCEPTION_OBJECTS");
  app.add_option("--threshold", opt.threshold_m, "x-y match distance for --log [m]")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-gap", opt.max_time_gap_s,
                 "--log: ground truth farther than this from a perception frame is not used [s]")
      ->check(CLI::PositiveNumber);
  app.add_option("--max-range", opt.max_range_m,
                 "--log: ignore ground-truth objects farther than this from the robot [m], 0 = all")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--include-tentative", opt.include_tentative, "--log: count tentative tracks as hypotheses");
  app.add_flag("--exclude-coasting", opt.exclude_coasting, "--log: do not count coasting tracks");
  auto* objects_opt = app.add_option("--objects-log", opt.objects_log,
                                     "--log: take PERCEPTION_OBJECTS from this log instead (a replay's output, "
                                     "e.g. ucon-replay --node perception --in LOG)");
  auto* gt_opt = app.add_option("--gt", gt_path, "MOTChallenge ground-truth text file");
  auto* pred_opt = app.add_option("--pred", pred_path, "MOTChallenge prediction text file");
  app.add_option("--iou", iou, "minimum IoU of a box match for --gt/--pred")->check(CLI::Range(0.0, 1.0));
  app.add_flag("--json", json, "print one JSON object instead of a table");
  app.add_flag("--allow-truncated", allow_truncated, "--log: evaluate what precedes a truncated or corrupt tail");
  log_opt->excludes(gt_opt)->excludes(pred_opt);
  gt_opt->needs(pred_opt);
  objects_opt->needs(log_opt);
  pred_opt->needs(gt_opt);
  CLI11_PARSE(app, argc, argv);

  opt.allow_truncated = allow_truncated;
  if (!log_path.empty()) {
    ucon::mot::LogMatchStats stats;
    std::string err;
    auto summary = ucon::mot::evaluateLog(log_path, opt, &stats, &err);
    if (!summary) {
      std::cerr << "ucon-mot: error: " << err << "\n";
      return 1;
    }
    if (stats.truncated) std::cerr << "ucon-mot: warning: " << stats.warning << "\n";
    if (json) {
      printJson(*summary, &stats);
    } else {
      printTable(*summary, "m");
      std::printf("%-22s %lld evaluated, %lld without ground truth, %lld invalid, %lld undecodable\n",
                  "log frames", static_cast<long long>(stats.frames_evaluated),
                  static_cast<long long>(stats.frames_without_ground_truth),
                  static_cast<long long>(stats.invalid_frames),
                  static_cast<long long>(stats.undecodable_messages));
    }
    return 0;
  }
  if (!gt_path.empty()) {
    std::string err;
    const auto gt_text = ucon::runtime::readTextFile(gt_path, &err);
    if (!gt_text) {
      std::cerr << "ucon-mot: error: " << err << "\n";
      return 1;
    }
    const auto pred_text = ucon::runtime::readTextFile(pred_path, &err);
    if (!pred_text) {
      std::cerr << "ucon-mot: error: " << err << "\n";
      return 1;
    }
    const auto gt = ucon::mot::parseMotChallenge(*gt_text, gt_path, &err);
    if (!gt) {
      std::cerr << "ucon-mot: error: " << err << "\n";
      return 1;
    }
    const auto pred = ucon::mot::parseMotChallenge(*pred_text, pred_path, &err);
    if (!pred) {
      std::cerr << "ucon-mot: error: " << err << "\n";
      return 1;
    }
    const auto s = ucon::mot::evaluateBoxes(*gt, *pred, iou);
    if (json) {
      printJson(s, nullptr);
    } else {
      printTable(s, "(1 - IoU)");
    }
    return 0;
  }
  std::cerr << "ucon-mot: error: give --log FILE, or --gt FILE --pred FILE (see --help)\n";
  return 2;
}
