// The Java classes in ucon_lcmtypes.jar (used by lcm-spy) and the C++ headers must agree on
// every type's fingerprint, or lcm-spy would decode nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <sstream>
#include <string>

#include "ucon/all_types.hpp"

namespace {

std::map<std::string, std::string> javaFingerprints() {
  const std::string cmd = std::string(UCON_JAVA) + " -cp " + UCON_TYPES_JAR + ":" + UCON_LCM_JAR +
                          " " + UCON_JAVA_SRC + " " + UCON_TYPES_JAR + " 2>&1";
  std::map<std::string, std::string> out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char line[512];
  while (fgets(line, sizeof(line), p)) {
    std::istringstream ss(line);
    std::string name, hex;
    if (ss >> name >> hex) out[name] = hex;
  }
  pclose(p);
  return out;
}

std::string hex(int64_t v) {
  std::ostringstream ss;
  ss << std::hex << static_cast<uint64_t>(v);
  return ss.str();
}

}  // namespace

TEST(Fingerprints, GivenTheTypesJarThenEveryCppTypeHasAJavaClassWithTheSameFingerprint) {
  const auto java = javaFingerprints();
  int count = 0;
#define UCON_CHECK_TYPE(T)                                                       \
  {                                                                              \
    const std::string name = std::string("ucon.") + #T;                          \
    auto it = java.find(name);                                                   \
    ASSERT_NE(it, java.end()) << "no Java class for " << name;                   \
    EXPECT_EQ(it->second, hex(ucon::T::getHash())) << "fingerprint of " << name; \
    ++count;                                                                     \
  }
  UCON_FOR_EACH_LCM_TYPE(UCON_CHECK_TYPE)
#undef UCON_CHECK_TYPE
  EXPECT_EQ(static_cast<std::size_t>(count), java.size()) << "jar holds classes C++ does not know";
}
