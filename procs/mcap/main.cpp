// ucon-mcap: turns an LCM log of a run into an MCAP file that Foxglove opens: every ucon
// channel as JSON with its schema, plus point clouds, transforms, poses, tracked objects with
// their covariance ellipses and uncertainty sectors, the planned trajectory and the static
// map in Foxglove's own schemas. A damaged log stops the export at the damage: the error
// names the byte offset, and the MCAP holds everything before it (a complete, valid file).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "ucon/foxglove/mcap_export.hpp"
#include "ucon/runtime/config_file.hpp"
#include "ucon/runtime/log_reader.hpp"

#ifndef UCON_SOURCE_DIR
#define UCON_SOURCE_DIR "."
#endif

namespace {

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};

}  // namespace

int main(int argc, char** argv) {
  namespace fg = ucon::foxglove;
  CLI::App app{"Convert an LCM log of a run into an MCAP file for Foxglove."};
  app.option_defaults()->always_capture_default();
  std::string log, out, compression = "zstd";
  std::string planner_config = std::string(UCON_SOURCE_DIR) + "/deploy/config/planner.yaml";
  fg::McapWriterOptions wopt;
  fg::ExportOptions eopt;
  double chunk_mb = 4.0;
  bool no_raw = false, no_foxglove = false, quiet = false;
  app.add_option("log", log, "LCM log to read (run_*.lcm)")->required();
  app.add_option("-o,--output", out, "MCAP file to write")->required();
  app.add_option("--compression", compression, "chunk compression: zstd, lz4 or none")
      ->check(CLI::IsMember({"zstd", "lz4", "none"}));
  app.add_option("--zstd-level", wopt.zstd_level, "zstd level, 1 (fastest) to 19 (smallest)")->check(CLI::Range(1, 19));
  app.add_option("--chunk-mb", chunk_mb, "uncompressed size at which a chunk is closed [MB]")
      ->check(CLI::Range(0.01, 512.0));
  app.add_option("--planner-config", planner_config,
                 "planner.yaml whose sector (h, k, kappa, s), body radius and map band the views use");
  app.add_flag("--no-raw", no_raw, "leave out the ucon messages as JSON (Foxglove views only)");
  app.add_flag("--no-foxglove", no_foxglove, "leave out the Foxglove views (ucon messages as JSON only)");
  app.add_flag("-q,--quiet", quiet, "print errors only");
  CLI11_PARSE(app, argc, argv);
  if (no_raw && no_foxglove) {
    std::fprintf(stderr, "ucon-mcap: error: --no-raw and --no-foxglove together leave nothing to write\n");
    return 2;
  }
  fg::parseCompression(compression, &wopt.compression);
  wopt.chunk_size = static_cast<std::size_t>(chunk_mb * 1024 * 1024);
  wopt.library = "ucon-mcap";
  wopt.background = true;  // chunks are compressed and written while the next one is filled
  eopt.raw_json = !no_raw;
  eopt.foxglove = !no_foxglove;

  std::string err;
  const auto yaml = ucon::runtime::readTextFile(planner_config, &err);
  if (!yaml) {
    std::fprintf(stderr, "ucon-mcap: error: %s (the views need the planner's config: --planner-config)\n",
                 err.c_str());
    return 2;
  }
  const auto view = fg::viewParamsFromPlannerYaml(*yaml, planner_config, &err);
  if (!view) {
    std::fprintf(stderr, "ucon-mcap: error: %s\n", err.c_str());
    return 2;
  }

  ucon::runtime::LogReader reader;
  if (!reader.open(log)) {
    std::fprintf(stderr, "ucon-mcap: error: %s\n", reader.error().c_str());
    return 2;
  }
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(out.c_str(), "wb"));
  if (!file) {
    std::fprintf(stderr, "ucon-mcap: error: cannot create %s\n", out.c_str());
    return 2;
  }
  static char buffer[1 << 20];
  std::setvbuf(file.get(), buffer, _IOFBF, sizeof(buffer));
  std::FILE* f = file.get();
  fg::McapWriter writer([f](const uint8_t* d, std::size_t n) { return std::fwrite(d, 1, n, f) == n; }, wopt);
  fg::McapExporter exporter(&writer, *view, eopt);

  const auto t0 = std::chrono::steady_clock::now();
  bool ok = writer.start();
  ucon::runtime::LogEvent ev;
  ucon::runtime::LogReadStatus st = ucon::runtime::LogReadStatus::kOk;
  while (ok && (st = reader.next(&ev)) == ucon::runtime::LogReadStatus::kOk) {
    ok = exporter.add(ev.channel, ev.data.data(), ev.data.size());
  }
  // A damaged log still gives a complete MCAP of everything before the damage.
  ok = ok && exporter.finish();
  const bool closed = std::fclose(file.release()) == 0;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!ok || !closed) {
    std::fprintf(stderr, "ucon-mcap: error: writing %s failed: %s\n", out.c_str(),
                 writer.error().empty() ? "cannot write the file" : writer.error().c_str());
    return 1;
  }

  const auto& s = writer.stats();
  const auto& es = exporter.stats();
  for (const auto& [ch, n] : es.unknown_type)
    std::fprintf(stderr, "ucon-mcap: warning: %lld events on %s are of no ucon type (left out)\n",
                 static_cast<long long>(n), ch.c_str());
  for (const auto& [ch, n] : es.undecodable)
    std::fprintf(stderr, "ucon-mcap: warning: %lld events on %s do not decode (left out)\n",
                 static_cast<long long>(n), ch.c_str());
  const bool damaged = st != ucon::runtime::LogReadStatus::kEnd;
  if (es.events == 0 && !damaged) std::fprintf(stderr, "ucon-mcap: warning: %s has no events\n", log.c_str());
  if (damaged) {
    std::fprintf(stderr,
                 "ucon-mcap: error: %s\nucon-mcap: %s holds the %lld events before it (%lld MCAP messages), "
                 "a complete MCAP file\n",
                 reader.error().c_str(), out.c_str(), static_cast<long long>(es.events),
                 static_cast<long long>(s.messages));
  }
  if (!quiet) {
    const double span = s.messages > 0 ? 1e-9 * static_cast<double>(s.end_time - s.start_time) : 0.0;
    std::printf("ucon-mcap: wrote %s: %lld events -> %llu messages on %u topics, %.1f s of log time, "
                "%u chunks (%s), %.1f MB (%.1f MB uncompressed), in %.2f s\n",
                out.c_str(), static_cast<long long>(es.events), static_cast<unsigned long long>(s.messages),
                s.channels, span, s.chunks, compression.c_str(), s.bytes / 1e6, s.uncompressed_bytes / 1e6,
                seconds);
    if (es.untimed > 0)
      std::printf("ucon-mcap: %lld messages without a usable message time (utime invalid, or wall clock while "
                  "the run is on sensor or simulation time) took the run's time where they were logged\n",
                  static_cast<long long>(es.untimed));
  }
  return damaged ? 2 : 0;
}
