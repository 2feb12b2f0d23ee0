// CRC check values (docs/reference.md; the catalogue's "123456789" check strings).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ucon/livox/crc.hpp"

using namespace ucon::livox;

namespace {
std::vector<uint8_t> bytesOf(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }
}  // namespace

TEST(LivoxCrc, GivenTheCheckStringThenCrc16CcittFalseIs29B1) {
  EXPECT_EQ(crc16CcittFalse(bytesOf("123456789")), 0x29B1);
}

TEST(LivoxCrc, GivenTheCheckStringThenCrc32IsCBF43926) {
  EXPECT_EQ(crc32(bytesOf("123456789")), 0xCBF43926u);
}

TEST(LivoxCrc, GivenEmptyInputThenTheCrcsAreTheirInitialValuesFinalised) {
  EXPECT_EQ(crc16CcittFalse(nullptr, 0), 0xFFFF);
  EXPECT_EQ(crc32(nullptr, 0), 0u);
}

TEST(LivoxCrc, GivenOneFlippedBitThenBothCrcsChange) {
  std::vector<uint8_t> a = bytesOf("The quick brown fox jumps over the lazy dog");
  std::vector<uint8_t> b = a;
  b[10] ^= 0x04;
  EXPECT_NE(crc16CcittFalse(a), crc16CcittFalse(b));
  EXPECT_NE(crc32(a), crc32(b));
  EXPECT_EQ(crc32(a), 0x414FA339u);  // well-known CRC-32 of this sentence
}
