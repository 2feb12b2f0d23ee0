#include "ucon/tools/health_view.hpp"

#include <algorithm>
#include <cstdio>
#include <set>

namespace ucon {
namespace tools {

namespace {
const std::set<std::string>& faultWords() {
  static const std::set<std::string> words = {
      "bad",      "collisions", "crc",      "drop",       "drops",    "dropped",   "error",
      "errors",   "expired",    "fail",     "failed",     "failures", "gaps",      "ignored",
      "invalid",  "late",       "lost",     "malformed",  "mismatches", "missed",  "nan",
      "older",    "overflow",   "overflows", "overrun",   "overruns", "refused",   "rejected",
      "reinitialisations", "resets", "skipped", "stale",  "timeout",  "timeouts",  "truncated",
      "undecodable", "unknown", "wrong"};
  return words;
}
}  // namespace

bool isFaultCounter(const std::string& name) {
  for (const char* phrase : {"out_of_order", "non_finite", "no_pose"}) {
    if (name.find(phrase) != std::string::npos) return true;
  }
  std::size_t start = 0;
  while (start <= name.size()) {
    const std::size_t end = std::min(name.find('_', start), name.size());
    if (faultWords().count(name.substr(start, end - start))) return true;
    start = end + 1;
  }
  return false;
}

std::string healthName(int8_t health) {
  switch (health) {
    case process_status_t::HEALTH_OK: return "OK";
    case process_status_t::HEALTH_WARN: return "WARN";
    case process_status_t::HEALTH_ERROR: return "ERROR";
  }
  return "health " + std::to_string(health);
}

void HealthView::add(const std::string& channel, const process_status_t& msg) {
  const std::string name = msg.name.empty() ? channel : msg.name;
  auto it = std::find_if(heard_.begin(), heard_.end(), [&](const HealthEntry& e) { return e.name == name; });
  if (it == heard_.end()) {
    heard_.push_back(HealthEntry{});
    it = heard_.end() - 1;
    it->name = name;
  }
  it->channel = channel;
  it->health = msg.health;
  it->message = msg.message;
  it->faults.clear();
  const std::size_t n = std::min({static_cast<std::size_t>(std::max(msg.num_counters, 0)),
                                   msg.counter_names.size(), msg.counter_values.size()});
  for (std::size_t i = 0; i < n; ++i) {
    if (msg.counter_values[i] > 0 && isFaultCounter(msg.counter_names[i])) {
      it->faults.emplace_back(msg.counter_names[i], msg.counter_values[i]);
    }
  }
  ++it->messages;
}

std::vector<HealthEntry> HealthView::entries(const std::vector<std::string>& expected) const {
  std::vector<HealthEntry> out;
  for (const std::string& name : expected) {
    auto it = std::find_if(heard_.begin(), heard_.end(), [&](const HealthEntry& e) { return e.name == name; });
    if (it != heard_.end()) {
      out.push_back(*it);
    } else {
      HealthEntry missing;
      missing.name = name;
      missing.health = -1;
      out.push_back(missing);
    }
  }
  std::vector<HealthEntry> others;
  for (const HealthEntry& e : heard_) {
    if (std::find(expected.begin(), expected.end(), e.name) == expected.end()) others.push_back(e);
  }
  std::sort(others.begin(), others.end(), [](const HealthEntry& a, const HealthEntry& b) { return a.name < b.name; });
  out.insert(out.end(), others.begin(), others.end());
  return out;
}

std::string HealthView::format(const std::vector<std::string>& expected, double listened_s) const {
  std::string out;
  char line[512];
  for (const HealthEntry& e : entries(expected)) {
    if (e.messages == 0) {
      std::snprintf(line, sizeof(line), "%-18s %-6s no status heard in %.1f s\n", e.name.c_str(), "-", listened_s);
      out += line;
      continue;
    }
    std::snprintf(line, sizeof(line), "%-18s %-6s %s\n", e.name.c_str(), healthName(e.health).c_str(),
                  e.message.empty() ? "-" : e.message.c_str());
    out += line;
    if (!e.faults.empty()) {
      std::string f = std::string(26, ' ') + "faults:";
      for (const auto& [name, value] : e.faults) f += " " + name + "=" + std::to_string(value);
      out += f + "\n";
    }
  }
  return out;
}

}  // namespace tools
}  // namespace ucon
