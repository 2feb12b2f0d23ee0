#pragma once
/// @file planner_variant.hpp
/// `ucon-bench-nav --planner-model M[,M...]` and `--check-growth K`: the shipped planner.yaml
/// with its obstacle model replaced (sector | no_uncertainty | fapp, the methods of Table II)
/// and, optionally, the covariance growth that every method shares outside the cost (the
/// post-check's `optimizer.check_uncertainty_k` and the fallback's `fallback.uncertainty_k`)
/// set to K for all of them. With K = 0 the sector's cost is the only place a covariance acts.

#include <string>

namespace ucon::bench::nav {

/// The planner.yaml text `yaml` with `optimizer.obstacle_model` = `model` (unless empty) and,
/// when `check_growth` >= 0, both growth keys = `check_growth`. False and `error` (naming the
/// key) when the text does not parse, a key is missing or the result is not a valid planner
/// config (an unknown model, a growth out of range).
bool plannerVariant(const std::string& yaml, const std::string& model, double check_growth, std::string* out,
                    std::string* error);

}  // namespace ucon::bench::nav
