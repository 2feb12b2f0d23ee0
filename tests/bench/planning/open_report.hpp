#pragma once
/// @file open_report.hpp
/// Tables and JSON of the open-loop protocol (issue 31): per horizon, density and method the
/// share of contact-free plans (all, avoidable, passing the check), McNemar's test of the
/// sector against each baseline on the paired plans, and breakdowns by the nearest mover's
/// track age and motion kind.

#include <cstdint>
#include <string>
#include <vector>

#include "open_loop.hpp"

namespace ucon::bench {

struct OpenRunKey {
  int n_dynamic = 0;
  uint64_t seed = 0;
};

/// Prints the tables (each headed by `command`) and, with a non-empty `json_path`, writes the
/// JSON (`settings_json`: the object's members describing the run, without braces). Returns
/// false if the JSON could not be written.
bool reportOpenLoop(const std::vector<OpenRunKey>& keys, const std::vector<OpenLoopResult>& runs,
                    const std::vector<std::string>& methods, const std::vector<double>& horizons,
                    const std::vector<int>& densities, const std::string& command, const std::string& settings_json,
                    const std::string& json_path);

/// Track-age bin of a probe: "<0.5 s", "0.5-2 s", ">2 s" or "untracked" (age < 0).
const char* trackAgeBin(double age_s);

}  // namespace ucon::bench
