#pragma once
/// @file config.hpp
/// Typed, validated reading of YAML configuration into parameter structs.
///
/// Parameter structs have named fields with in-class defaults and a `read(ConfigReader&)`
/// that maps YAML keys one-to-one onto fields with their ranges. Every error names the full
/// dotted key ("planner.sector.alpha"). Keys are required: a missing key, a key of the wrong
/// type, a value out of range and an unknown key (a typo) are all errors. This library parses
/// text only; reading the file is the process's job.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ucon {

/// One configuration problem, naming the key it is about.
struct ConfigError {
  std::string key;      ///< dotted key path, empty for a document-level error
  std::string message;  ///< what is wrong
  /// "config error at 'a.b': message" (with the source name when known).
  std::string toString() const;
};

/// Reader over one YAML mapping. Cheap to copy; copies share the error list.
class ConfigReader {
 public:
  /// Parses YAML text. `source` names it in messages (a file path). On a syntax error or a
  /// document that is not a mapping, returns nullopt and fills `error`.
  static std::optional<ConfigReader> parse(const std::string& yaml_text, const std::string& source,
                                           ConfigError* error);

  ~ConfigReader();
  ConfigReader(const ConfigReader&);
  ConfigReader& operator=(const ConfigReader&);

  /// Each read stores the value in `out` when the key is present, of the right type and in
  /// [min, max]; otherwise records an error naming the key and leaves `out` unchanged.
  void read(const std::string& key, double& out, double min, double max);
  void read(const std::string& key, float& out, float min, float max);
  void read(const std::string& key, int& out, int min, int max);
  void read(const std::string& key, int64_t& out, int64_t min, int64_t max);
  void read(const std::string& key, bool& out);
  /// String; when `allowed` is not empty the value must be one of them.
  void read(const std::string& key, std::string& out, const std::vector<std::string>& allowed = {});
  /// Sequence of numbers, each in [min, max]; `size` 0 = any length.
  void read(const std::string& key, std::vector<double>& out, std::size_t size, double min,
            double max);

  /// True if `key` is present (does not mark it as used).
  bool has(const std::string& key) const;

  /// Reader over the nested mapping `key`; records an error (and returns an empty reader) if
  /// it is missing or not a mapping.
  ConfigReader section(const std::string& key);

  /// Readers over the list of mappings `key` (e.g. a list of sensors), one per element, named
  /// "key[i]" in errors. Records an error (and returns none) if it is missing or not a list
  /// of mappings; an empty list gives none.
  std::vector<ConfigReader> sections(const std::string& key);

  /// Records an error for `key` (for cross-field checks in a struct's validate()).
  void fail(const std::string& key, const std::string& message);

  /// Records an error for every key of this mapping (and of sections taken from it) that no
  /// read() asked for: catches typos that would otherwise silently keep a default.
  void rejectUnknownKeys();

  bool ok() const;
  const std::vector<ConfigError>& errors() const;
  /// All errors, one per line.
  std::string errorText() const;

 private:
  struct Impl;
  explicit ConfigReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Parses `yaml_text` into a parameter struct P (which has `void read(ConfigReader&)`), rejects
/// unknown keys, and returns the struct or the errors.
template <class P>
std::optional<P> loadParams(const std::string& yaml_text, const std::string& source,
                            std::vector<ConfigError>* errors) {
  ConfigError parse_error;
  auto reader = ConfigReader::parse(yaml_text, source, &parse_error);
  if (!reader) {
    if (errors) errors->push_back(parse_error);
    return std::nullopt;
  }
  P params;
  params.read(*reader);
  reader->rejectUnknownKeys();
  if (!reader->ok()) {
    if (errors) *errors = reader->errors();
    return std::nullopt;
  }
  return params;
}

}  // namespace ucon
