#include "ucon/runtime/log_compare.hpp"

#include <regex>

#include "ucon/fields.hpp"
#include "ucon/runtime/log_reader.hpp"

namespace ucon {
namespace runtime {

namespace {
// Next event matching the filter; kOk, kEnd or an error status.
LogReadStatus nextMatching(LogReader& r, const std::regex* re, LogEvent* e) {
  while (true) {
    const auto s = r.next(e);
    if (s != LogReadStatus::kOk) return s;
    if (!re || std::regex_match(e->channel, *re)) return s;
  }
}

std::string describeDiff(const LogEvent& a, const LogEvent& b) {
  std::string ta, tb;
  FieldList fa, fb;
  const bool da = decodeFields(a.data.data(), static_cast<int>(a.data.size()), &ta, &fa);
  const bool db = decodeFields(b.data.data(), static_cast<int>(b.data.size()), &tb, &fb);
  if (!da || !db) return "payload differs (" + std::to_string(a.data.size()) + " vs " +
                         std::to_string(b.data.size()) + " bytes, not a known ucon type)";
  if (ta != tb) return "type " + ta + " vs " + tb;
  for (std::size_t i = 0; i < fa.size() && i < fb.size(); ++i) {
    if (fa[i].first != fb[i].first) {
      return "(" + ta + ") field " + fa[i].first + " present in one log, " + fb[i].first + " in the other";
    }
    if (fa[i].second != fb[i].second) {
      return "(" + ta + ") field " + fa[i].first + ": " + fa[i].second + " vs " + fb[i].second;
    }
  }
  return "(" + ta + ") " + std::to_string(fa.size()) + " vs " + std::to_string(fb.size()) + " fields";
}
}  // namespace

LogComparison compareLogs(const std::string& a, const std::string& b,
                          const std::string& channel_regex) {
  LogComparison out;
  LogReader ra, rb;
  if (!ra.open(a) || !rb.open(b)) {
    out.error = true;
    out.message = !ra.error().empty() ? ra.error() : rb.error();
    return out;
  }
  std::regex re;
  const std::regex* filter = nullptr;
  if (!channel_regex.empty()) {
    re = std::regex(channel_regex);
    filter = &re;
  }
  LogEvent ea, eb;
  while (true) {
    const auto sa = nextMatching(ra, filter, &ea);
    const auto sb = nextMatching(rb, filter, &eb);
    if (sa != LogReadStatus::kOk && sa != LogReadStatus::kEnd) {
      out.error = true;
      out.message = ra.error();
      return out;
    }
    if (sb != LogReadStatus::kOk && sb != LogReadStatus::kEnd) {
      out.error = true;
      out.message = rb.error();
      return out;
    }
    if (sa == LogReadStatus::kEnd && sb == LogReadStatus::kEnd) break;
    const std::string where = "event " + std::to_string(out.events_compared);
    if (sa == LogReadStatus::kEnd || sb == LogReadStatus::kEnd) {
      out.message = where + ": " + (sa == LogReadStatus::kEnd ? a : b) + " ends here, the other log has " +
                    (sa == LogReadStatus::kEnd ? eb.channel : ea.channel);
      return out;
    }
    if (ea.channel != eb.channel) {
      out.message = where + ": channel " + ea.channel + " vs " + eb.channel;
      return out;
    }
    if (ea.data != eb.data) {
      out.message = where + " on " + ea.channel + " " + describeDiff(ea, eb);
      return out;
    }
    ++out.events_compared;
  }
  out.identical = true;
  return out;
}

}  // namespace runtime
}  // namespace ucon
