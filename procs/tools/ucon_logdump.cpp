// ucon-logdump: prints an LCM log as text (every field of every ucon message), or compares two
// logs and names the first message and field that differ.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <regex>

#include "ucon/fields.hpp"
#include "ucon/runtime/log_compare.hpp"
#include "ucon/runtime/log_reader.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Print an LCM log as text, or compare two logs (--compare)."};
  std::string path, compare, channel;
  long max_events = -1;
  bool summary = false;
  app.add_option("log", path, "LCM log file")->required();
  app.add_option("--channel", channel, "only channels matching this regex");
  app.add_option("--max", max_events, "stop after this many events");
  app.add_flag("--summary", summary, "one line per channel: count and bytes");
  app.add_option("--compare", compare, "compare with this log; exit 1 at the first difference");
  CLI11_PARSE(app, argc, argv);

  if (!compare.empty()) {
    const auto c = ucon::runtime::compareLogs(path, compare, channel);
    if (c.error) {
      std::fprintf(stderr, "ucon-logdump: error: %s\n", c.message.c_str());
      return 2;
    }
    if (c.identical) {
      std::printf("identical: %ld events\n", c.events_compared);
      return 0;
    }
    std::printf("differ: %s\n", c.message.c_str());
    return 1;
  }

  ucon::runtime::LogReader r;
  if (!r.open(path)) {
    std::fprintf(stderr, "ucon-logdump: error: %s\n", r.error().c_str());
    return 2;
  }
  std::regex re(channel.empty() ? ".*" : channel);
  std::map<std::string, std::pair<long, long>> counts;
  ucon::runtime::LogEvent e;
  long n = 0;
  ucon::runtime::LogReadStatus s;
  while ((s = r.next(&e)) == ucon::runtime::LogReadStatus::kOk) {
    if (!std::regex_match(e.channel, re)) continue;
    if (max_events >= 0 && n >= max_events) break;
    ++n;
    auto& c = counts[e.channel];
    ++c.first;
    c.second += static_cast<long>(e.data.size());
    if (summary) continue;
    std::string type;
    ucon::FieldList fields;
    if (ucon::decodeFields(e.data.data(), static_cast<int>(e.data.size()), &type, &fields)) {
      std::printf("#%ld t=%lld %s %s\n", static_cast<long>(e.event_number),
                  static_cast<long long>(e.timestamp), e.channel.c_str(), type.c_str());
      for (const auto& [k, v] : fields) std::printf("  %s = %s\n", k.c_str(), v.c_str());
    } else {
      std::printf("#%ld t=%lld %s (%zu bytes, not a ucon type)\n", static_cast<long>(e.event_number),
                  static_cast<long long>(e.timestamp), e.channel.c_str(), e.data.size());
    }
  }
  if (summary) {
    for (const auto& [ch, c] : counts) std::printf("%-24s %8ld msgs %12ld bytes\n", ch.c_str(), c.first, c.second);
  }
  if (s != ucon::runtime::LogReadStatus::kOk && s != ucon::runtime::LogReadStatus::kEnd) {
    std::fprintf(stderr, "ucon-logdump: error: %s\n", r.error().c_str());
    return 2;
  }
  return 0;
}
