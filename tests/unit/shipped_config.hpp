#pragma once
// ShippedConfig<P>: loads deploy/config/<process>.yaml into P and checks it field by field
// against P's in-class defaults; expectEveryKeyChecked() fails for a key of the file that no
// expect() named.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <optional>
#include <set>
#include <string>

#include "ucon/config.hpp"
#include "ucon/runtime/config_file.hpp"

namespace test_support {

template <class P>
class ShippedConfig {
 public:
  explicit ShippedConfig(const std::string& path) : path_(path) {
    std::string err;
    const auto text = ucon::runtime::readTextFile(path, &err);
    if (!text) {
      ADD_FAILURE() << err;
      return;
    }
    std::vector<ucon::ConfigError> errors;
    shipped_ = ucon::loadParams<P>(*text, path, &errors);
    for (const auto& e : errors) ADD_FAILURE() << e.toString();
    collect(YAML::Load(*text), "");
  }

  bool loaded() const { return shipped_.has_value(); }
  const P& shipped() const { return *shipped_; }

  template <class T>
  void expect(const std::string& key, const T& shipped, const T& in_class) {
    EXPECT_EQ(shipped, in_class) << path_ << ": '" << key << "' differs from the in-class default";
    checked_.insert(key);
  }

  void expectEveryKeyChecked() const {
    for (const auto& k : keys_) EXPECT_TRUE(checked_.count(k)) << path_ << ": key '" << k << "' is not checked";
  }

 private:
  void collect(const YAML::Node& n, const std::string& prefix) {
    for (const auto& kv : n) {
      const std::string key = prefix + kv.first.as<std::string>();
      if (kv.second.IsMap()) {
        collect(kv.second, key + ".");
      } else {
        keys_.insert(key);
      }
    }
  }

  std::string path_;
  std::optional<P> shipped_;
  std::set<std::string> keys_;
  std::set<std::string> checked_;
};

}  // namespace test_support
