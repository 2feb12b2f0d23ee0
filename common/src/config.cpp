#include "ucon/config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace ucon {

namespace {

struct SharedState {
  std::string source;
  std::vector<ConfigError> errors;
  // Keys asked for, per mapping (identified by its dotted prefix).
  std::map<std::string, std::set<std::string>> used;
  // Mappings handed out, so rejectUnknownKeys() can check nested sections too.
  std::map<std::string, YAML::Node> mappings;
};

std::string join(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

std::string describe(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a mapping";
  return "nothing";
}

template <class T>
std::string str(T v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace

std::string ConfigError::toString() const {
  if (key.empty()) return "config error: " + message;
  return "config error at '" + key + "': " + message;
}

struct ConfigReader::Impl {
  std::shared_ptr<SharedState> state;
  YAML::Node node;  // the mapping (may be null for a missing section)
  std::string prefix;

  void error(const std::string& key, const std::string& msg) {
    std::string m = msg;
    if (!state->source.empty()) m += " (in " + state->source + ")";
    state->errors.push_back({join(prefix, key), m});
  }

  // The node for `key` if present; records "missing" otherwise.
  std::optional<YAML::Node> get(const std::string& key) {
    state->used[prefix].insert(key);
    if (!node || !node.IsMap()) {
      // The section itself is missing; its error is already recorded.
      return std::nullopt;
    }
    YAML::Node n = node[key];
    if (!n || n.IsNull()) {
      error(key, "missing key");
      return std::nullopt;
    }
    return n;
  }

  // Parses a scalar as a number of type T; records a type error otherwise.
  template <class T>
  std::optional<T> number(const std::string& key, const YAML::Node& n, const char* what) {
    if (!n.IsScalar()) {
      error(key, std::string("expected ") + what + ", got " + describe(n));
      return std::nullopt;
    }
    T v{};
    try {
      v = n.as<T>();
    } catch (const YAML::Exception&) {
      error(key, std::string("expected ") + what + ", got " + describe(n));
      return std::nullopt;
    }
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(v)) {
        error(key, "expected a finite number, got " + describe(n));
        return std::nullopt;
      }
    }
    return v;
  }

  template <class T>
  void readRange(const std::string& key, T& out, T min, T max, const char* what) {
    auto n = get(key);
    if (!n) return;
    auto v = number<T>(key, *n, what);
    if (!v) return;
    if (*v < min || *v > max) {
      error(key, "value " + str(*v) + " out of range [" + str(min) + ", " + str(max) + "]");
      return;
    }
    out = *v;
  }
};

ConfigReader::ConfigReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ConfigReader::~ConfigReader() = default;
ConfigReader::ConfigReader(const ConfigReader& o) : impl_(std::make_unique<Impl>(*o.impl_)) {}
ConfigReader& ConfigReader::operator=(const ConfigReader& o) {
  if (this != &o) impl_ = std::make_unique<Impl>(*o.impl_);
  return *this;
}

std::optional<ConfigReader> ConfigReader::parse(const std::string& yaml_text,
                                                const std::string& source, ConfigError* error) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    if (error) {
      *error = {"", "YAML syntax error at line " + std::to_string(e.mark.line + 1) + ", column " +
                        std::to_string(e.mark.column + 1) + ": " + e.msg +
                        (source.empty() ? "" : " (in " + source + ")")};
    }
    return std::nullopt;
  }
  if (!root.IsMap()) {
    if (error) {
      *error = {"", "the document must be a mapping of keys to values, got " + describe(root) +
                        (source.empty() ? "" : " (in " + source + ")")};
    }
    return std::nullopt;
  }
  auto impl = std::make_unique<Impl>();
  impl->state = std::make_shared<SharedState>();
  impl->state->source = source;
  impl->state->mappings[""] = root;
  impl->node = root;
  return ConfigReader(std::move(impl));
}

void ConfigReader::read(const std::string& key, double& out, double min, double max) {
  impl_->readRange<double>(key, out, min, max, "a number");
}

void ConfigReader::read(const std::string& key, float& out, float min, float max) {
  double v = out;
  impl_->readRange<double>(key, v, min, max, "a number");
  out = static_cast<float>(v);
}

void ConfigReader::read(const std::string& key, int& out, int min, int max) {
  impl_->readRange<int>(key, out, min, max, "an integer");
}

void ConfigReader::read(const std::string& key, int64_t& out, int64_t min, int64_t max) {
  impl_->readRange<int64_t>(key, out, min, max, "an integer");
}

void ConfigReader::read(const std::string& key, bool& out) {
  auto n = impl_->get(key);
  if (!n) return;
  bool v = false;
  if (!n->IsScalar() || !YAML::convert<bool>::decode(*n, v)) {
    impl_->error(key, "expected true or false, got " + describe(*n));
    return;
  }
  out = v;
}

void ConfigReader::read(const std::string& key, std::string& out,
                        const std::vector<std::string>& allowed) {
  auto n = impl_->get(key);
  if (!n) return;
  if (!n->IsScalar()) {
    impl_->error(key, "expected a string, got " + describe(*n));
    return;
  }
  const std::string v = n->Scalar();
  if (!allowed.empty()) {
    bool found = false;
    std::string list;
    for (const auto& a : allowed) {
      found = found || a == v;
      list += (list.empty() ? "" : ", ") + a;
    }
    if (!found) {
      impl_->error(key, "value '" + v + "' is not one of: " + list);
      return;
    }
  }
  out = v;
}

void ConfigReader::read(const std::string& key, std::vector<double>& out, std::size_t size,
                        double min, double max) {
  auto n = impl_->get(key);
  if (!n) return;
  if (!n->IsSequence()) {
    impl_->error(key, "expected a list of numbers, got " + describe(*n));
    return;
  }
  if (size != 0 && n->size() != size) {
    impl_->error(key, "expected " + std::to_string(size) + " numbers, got " +
                          std::to_string(n->size()));
    return;
  }
  std::vector<double> v;
  for (std::size_t i = 0; i < n->size(); ++i) {
    const std::string k = key + "[" + std::to_string(i) + "]";
    auto x = impl_->number<double>(k, (*n)[i], "a number");
    if (!x) return;
    if (*x < min || *x > max) {
      impl_->error(k, "value " + str(*x) + " out of range [" + str(min) + ", " + str(max) + "]");
      return;
    }
    v.push_back(*x);
  }
  out = std::move(v);
}

bool ConfigReader::has(const std::string& key) const {
  return impl_->node && impl_->node.IsMap() && impl_->node[key] && !impl_->node[key].IsNull();
}

ConfigReader ConfigReader::section(const std::string& key) {
  auto impl = std::make_unique<Impl>();
  impl->state = impl_->state;
  impl->prefix = join(impl_->prefix, key);
  auto n = impl_->get(key);
  if (n) {
    if (n->IsMap()) {
      impl->node = *n;
      impl_->state->mappings[impl->prefix] = *n;
    } else {
      impl_->error(key, "expected a mapping (a section of keys), got " + describe(*n));
    }
  }
  return ConfigReader(std::move(impl));
}

std::vector<ConfigReader> ConfigReader::sections(const std::string& key) {
  std::vector<ConfigReader> out;
  auto n = impl_->get(key);
  if (!n) return out;
  if (!n->IsSequence()) {
    impl_->error(key, "expected a list of mappings, got " + describe(*n));
    return out;
  }
  for (std::size_t i = 0; i < n->size(); ++i) {
    const YAML::Node e = (*n)[i];
    const std::string name = key + "[" + std::to_string(i) + "]";
    if (!e.IsMap()) {
      impl_->error(name, "expected a mapping (a section of keys), got " + describe(e));
      continue;
    }
    auto impl = std::make_unique<Impl>();
    impl->state = impl_->state;
    impl->prefix = join(impl_->prefix, name);
    impl->node = e;
    impl_->state->mappings[impl->prefix] = e;
    out.push_back(ConfigReader(std::move(impl)));
  }
  return out;
}

void ConfigReader::fail(const std::string& key, const std::string& message) {
  impl_->error(key, message);
}

void ConfigReader::rejectUnknownKeys() {
  auto& st = *impl_->state;
  for (const auto& [prefix, mapping] : st.mappings) {
    // Only this reader's mapping and the sections below it.
    if (!impl_->prefix.empty() && prefix != impl_->prefix &&
        prefix.rfind(impl_->prefix + ".", 0) != 0) {
      continue;
    }
    const auto& used = st.used[prefix];
    for (const auto& kv : mapping) {
      const std::string k = kv.first.as<std::string>();
      if (!used.count(k)) {
        st.errors.push_back({join(prefix, k), "unknown key (misspelt?)" +
                                                  (st.source.empty() ? std::string()
                                                                     : " (in " + st.source + ")")});
      }
    }
  }
}

bool ConfigReader::ok() const { return impl_->state->errors.empty(); }

const std::vector<ConfigError>& ConfigReader::errors() const { return impl_->state->errors; }

std::string ConfigReader::errorText() const {
  std::string out;
  for (const auto& e : impl_->state->errors) out += e.toString() + "\n";
  return out;
}

}  // namespace ucon
