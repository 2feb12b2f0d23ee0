#pragma once
/// @file config_file.hpp
/// Reads a YAML config file into a parameter struct (the I/O half of ucon/config.hpp).

#include <optional>
#include <string>
#include <vector>

#include "ucon/config.hpp"

namespace ucon {
namespace runtime {

/// Reads the whole file; nullopt (and `error`) if it cannot be opened.
std::optional<std::string> readTextFile(const std::string& path, std::string* error);

/// Loads `path` into P. On failure prints every error (each naming its key) to stderr,
/// prefixed with `process`, and returns nullopt.
template <class P>
std::optional<P> loadConfigFile(const std::string& process, const std::string& path);

/// Loads `path` into `*out` (and its text into `*text` if not null). False and `error` (the
/// path, then every error naming its key) if the file cannot be read or is not a valid P.
template <class P>
bool loadConfigFile(const std::string& path, P* out, std::string* text, std::string* error);

/// Prints config errors to stderr, one per line.
void printConfigErrors(const std::string& process, const std::vector<ConfigError>& errors);

template <class P>
std::optional<P> loadConfigFile(const std::string& process, const std::string& path) {
  std::string err;
  auto text = readTextFile(path, &err);
  if (!text) {
    printConfigErrors(process, {ConfigError{"", err}});
    return std::nullopt;
  }
  std::vector<ConfigError> errors;
  auto p = loadParams<P>(*text, path, &errors);
  if (!p) printConfigErrors(process, errors);
  return p;
}

template <class P>
bool loadConfigFile(const std::string& path, P* out, std::string* text, std::string* error) {
  auto t = readTextFile(path, error);
  if (!t) return false;
  std::vector<ConfigError> errors;
  auto p = loadParams<P>(*t, path, &errors);
  if (!p) {
    *error = path + ":";
    for (const auto& e : errors) *error += " " + e.toString();
    return false;
  }
  *out = *p;
  if (text) *text = *t;
  return true;
}

}  // namespace runtime
}  // namespace ucon
