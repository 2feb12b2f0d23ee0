// Config validation names the bad key for a missing key, an out-of-range value, a wrong
// type, an unknown key and a syntax error.
#include <gtest/gtest.h>

#include "ucon/config.hpp"

namespace {

struct FilterParams {
  double cutoff_hz = 5.0;  ///< [Hz] (0, 100]
  void read(ucon::ConfigReader& r) { r.read("cutoff_hz", cutoff_hz, 0.01, 100.0); }
};

struct ExampleParams {
  double rate_hz = 10.0;        ///< [Hz] [0.1, 100]
  int queue = 4;                ///< messages [1, 64]
  bool enabled = true;
  std::string mode = "sector";  ///< sector | fapp
  std::vector<double> mu = {0.3, 0.3, 0.4};
  FilterParams filter;
  void read(ucon::ConfigReader& r) {
    r.read("rate_hz", rate_hz, 0.1, 100.0);
    r.read("queue", queue, 1, 64);
    r.read("enabled", enabled);
    r.read("mode", mode, {"sector", "fapp"});
    r.read("mu", mu, 3, 0.0, 1.0);
    auto s = r.section("filter");
    filter.read(s);
  }
};

const char* kGood = R"(
rate_hz: 20
queue: 8
enabled: false
mode: fapp
mu: [0.2, 0.3, 0.5]
filter:
  cutoff_hz: 2.5
)";

std::vector<ucon::ConfigError> errorsFor(const std::string& yaml) {
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<ExampleParams>(yaml, "test.yaml", &errors);
  EXPECT_FALSE(p.has_value());
  return errors;
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

}  // namespace

TEST(Config, GivenACompleteFileThenEveryFieldIsRead) {
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<ExampleParams>(kGood, "test.yaml", &errors);
  ASSERT_TRUE(p.has_value()) << (errors.empty() ? "" : errors[0].toString());
  EXPECT_DOUBLE_EQ(p->rate_hz, 20.0);
  EXPECT_EQ(p->queue, 8);
  EXPECT_FALSE(p->enabled);
  EXPECT_EQ(p->mode, "fapp");
  EXPECT_DOUBLE_EQ(p->mu[2], 0.5);
  EXPECT_DOUBLE_EQ(p->filter.cutoff_hz, 2.5);
}

TEST(Config, GivenAMissingKeyThenTheErrorNamesIt) {
  const auto e = errorsFor(replace(kGood, "queue: 8\n", ""));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "queue");
  EXPECT_NE(e[0].toString().find("missing"), std::string::npos);
  EXPECT_NE(e[0].toString().find("test.yaml"), std::string::npos);
}

TEST(Config, GivenAnOutOfRangeValueThenTheErrorNamesTheKeyAndRange) {
  const auto e = errorsFor(replace(kGood, "cutoff_hz: 2.5", "cutoff_hz: 500"));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "filter.cutoff_hz");
  EXPECT_NE(e[0].message.find("out of range"), std::string::npos);
}

TEST(Config, GivenAWrongTypeThenTheErrorNamesTheKey) {
  auto e = errorsFor(replace(kGood, "queue: 8", "queue: eight"));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "queue");
  EXPECT_NE(e[0].message.find("integer"), std::string::npos);

  e = errorsFor(replace(kGood, "enabled: false", "enabled: 3"));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "enabled");

  e = errorsFor(replace(kGood, "mu: [0.2, 0.3, 0.5]", "mu: [0.2, x, 0.5]"));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "mu[1]");

  e = errorsFor(replace(kGood, "filter:\n  cutoff_hz: 2.5", "filter: 3"));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "filter");
}

TEST(Config, GivenAValueNotInTheAllowedSetThenTheErrorListsTheChoices) {
  const auto e = errorsFor(replace(kGood, "mode: fapp", "mode: magic"));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "mode");
  EXPECT_NE(e[0].message.find("sector, fapp"), std::string::npos);
}

TEST(Config, GivenNonFiniteNumbersThenTheyAreRejected) {
  const auto e = errorsFor(replace(kGood, "rate_hz: 20", "rate_hz: .nan"));
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "rate_hz");
}

TEST(Config, GivenAMisspeltKeyThenItIsReportedAsUnknown) {
  const auto e = errorsFor(std::string(kGood) + "  cutof_hz: 3\n");
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].key, "filter.cutof_hz");
  EXPECT_NE(e[0].message.find("unknown"), std::string::npos);
}

TEST(Config, GivenASyntaxErrorThenTheLineIsNamed) {
  std::vector<ucon::ConfigError> errors;
  auto p = ucon::loadParams<ExampleParams>("rate_hz: [1, 2\nqueue: 3\n", "bad.yaml", &errors);
  EXPECT_FALSE(p.has_value());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].message.find("line"), std::string::npos);
  EXPECT_NE(errors[0].message.find("bad.yaml"), std::string::npos);
}

TEST(Config, GivenADocumentThatIsNotAMappingThenItIsRejected) {
  std::vector<ucon::ConfigError> errors;
  EXPECT_FALSE(ucon::loadParams<ExampleParams>("- 1\n- 2\n", "list.yaml", &errors).has_value());
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].message.find("mapping"), std::string::npos);
}

TEST(Config, GivenAListOfMappingsThenEachElementIsReadAndItsErrorsNameTheIndex) {
  struct Item {
    double x = 0.0;
    void read(ucon::ConfigReader& r) { r.read("x", x, 0.0, 10.0); }
  };
  struct Listed {
    std::vector<Item> items;
    void read(ucon::ConfigReader& r) {
      for (auto& e : r.sections("items")) {
        items.emplace_back();
        items.back().read(e);
      }
    }
  };
  std::vector<ucon::ConfigError> errors;
  auto ok = ucon::loadParams<Listed>("items:\n  - {x: 1.5}\n  - {x: 2.5}\n", "", &errors);
  ASSERT_TRUE(ok.has_value());
  ASSERT_EQ(ok->items.size(), 2u);
  EXPECT_DOUBLE_EQ(ok->items[1].x, 2.5);
  EXPECT_TRUE(ucon::loadParams<Listed>("items: []\n", "", &errors)->items.empty());

  EXPECT_FALSE(ucon::loadParams<Listed>("items:\n  - {x: 1}\n  - {x: 20}\n", "", &errors));
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].key, "items[1].x");
  EXPECT_FALSE(ucon::loadParams<Listed>("items:\n  - {x: 1, y: 2}\n", "", &errors));
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].key, "items[0].y");  // unknown key inside an element
  EXPECT_FALSE(ucon::loadParams<Listed>("items: 3\n", "", &errors));
  EXPECT_FALSE(ucon::loadParams<Listed>("items:\n  - 3\n", "", &errors));
  ASSERT_FALSE(errors.empty());
  EXPECT_EQ(errors[0].key, "items[0]");
}
