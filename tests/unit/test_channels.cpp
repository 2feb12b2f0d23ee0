#include <gtest/gtest.h>

#include <set>

#include "ucon/all_types.hpp"
#include "ucon/channels.hpp"

TEST(Channels, GivenTheRegistryThenNamesAreUniqueAndTypesExist) {
  std::set<std::string> names;
  std::set<std::string> types;
#define UCON_NAME(T) types.insert(std::string("ucon.") + #T);
  UCON_FOR_EACH_LCM_TYPE(UCON_NAME)
#undef UCON_NAME
  for (const auto& c : ucon::channels::all()) {
    EXPECT_TRUE(names.insert(c.name).second) << "duplicate channel " << c.name;
    EXPECT_TRUE(types.count(c.type)) << c.name << " names unknown type " << c.type;
    EXPECT_GE(c.nominal_hz, 0.0);
  }
  ASSERT_NE(ucon::channels::find("LIDAR_POINTS"), nullptr);
  EXPECT_EQ(ucon::channels::find("LIDAR_POINTS")->type, "ucon.point_cloud_t");
  EXPECT_EQ(ucon::channels::find("NOPE"), nullptr);
}
