// MCAP writer: CRC, record layout, chunks and their indexes, summary and footer, read back by
// the independent parser of mcap_test_reader.hpp for every compression.
#include <gtest/gtest.h>

#include <string>

#include "mcap_test_reader.hpp"
#include "ucon/foxglove/mcap_writer.hpp"

namespace fg = ucon::foxglove;

namespace {

std::string writeSample(fg::McapCompression compression, std::size_t chunk_size, int messages,
                        bool background = false) {
  std::string out;
  fg::McapWriterOptions opt;
  opt.background = background;
  opt.compression = compression;
  opt.chunk_size = chunk_size;
  opt.library = "test";
  fg::McapWriter w([&](const uint8_t* d, std::size_t n) {
    out.append(reinterpret_cast<const char*>(d), n);
    return true;
  }, opt);
  EXPECT_TRUE(w.start());
  const uint16_t s1 = w.addSchema("a.A", "jsonschema", R"({"type":"object","properties":{}})");
  const uint16_t s2 = w.addSchema("b.B", "jsonschema", R"({"type":"object","properties":{}})");
  const uint16_t c0 = w.addChannel(s1, "/a", "json", {{"k", "v"}});
  const uint16_t c1 = w.addChannel(s2, "/b", "json");
  const uint16_t c2 = w.addChannel(s1, "/a2", "json");
  EXPECT_EQ(s1, 1);
  EXPECT_EQ(s2, 2);
  EXPECT_EQ(c0, 0);
  EXPECT_EQ(c2, 2);
  for (int i = 0; i < messages; ++i) {
    const uint16_t ch = i % 3 == 0 ? c0 : i % 3 == 1 ? c1 : c2;
    // Times not sorted across channels: every third message goes back 5 ms.
    const uint64_t t = 1'000'000'000ull + 10'000'000ull * i - (i % 3 == 2 ? 5'000'000ull : 0);
    const std::string data = "{\"i\":" + std::to_string(i) + "}";
    EXPECT_TRUE(w.write(ch, static_cast<uint32_t>(i), t, t, data.data(), data.size()));
  }
  EXPECT_TRUE(w.finish());
  EXPECT_TRUE(w.ok()) << w.error();
  return out;
}

}  // namespace

TEST(McapWriter, GivenTheCheckStringWhenCrcThenIsTheIsoHdlcValue) {
  EXPECT_EQ(fg::crc32(0, "123456789", 9), 0xCBF43926u);
  // Continued in two parts: the same.
  EXPECT_EQ(fg::crc32(fg::crc32(0, "1234", 4), "56789", 5), 0xCBF43926u);
}

TEST(McapWriter, GivenAnEmptyFileWhenWrittenThenMagicHeaderDataEndSummaryFooter) {
  std::string out;
  fg::McapWriter w([&](const uint8_t* d, std::size_t n) {
    out.append(reinterpret_cast<const char*>(d), n);
    return true;
  }, fg::McapWriterOptions{});
  ASSERT_TRUE(w.start());
  ASSERT_TRUE(w.finish());
  // Magic (8), Header record: opcode, length 12, profile "" and library "ucon" (4 + 0 + 4 + 4).
  ASSERT_GE(out.size(), 29u);
  EXPECT_EQ(out.substr(0, 8), std::string("\x89MCAP0\r\n", 8));
  EXPECT_EQ(static_cast<uint8_t>(out[8]), 0x01);
  EXPECT_EQ(out.substr(9, 8), std::string("\x0C\0\0\0\0\0\0\0", 8));
  EXPECT_EQ(out.substr(17, 12), std::string("\0\0\0\0\x04\0\0\0ucon", 12));
  // Data End follows directly: opcode 0x0F, length 4, the CRC of everything before it.
  EXPECT_EQ(static_cast<uint8_t>(out[29]), 0x0F);
  const uint32_t crc = static_cast<uint8_t>(out[38]) | (static_cast<uint8_t>(out[39]) << 8) |
                       (static_cast<uint8_t>(out[40]) << 16) | (uint32_t{static_cast<uint8_t>(out[41])} << 24);
  EXPECT_EQ(crc, fg::crc32(0, out.data(), 29));
  const auto f = mcap_test::parse(out);
  EXPECT_TRUE(f.errors.empty()) << f.errors.front();
  EXPECT_TRUE(f.has_statistics);
  EXPECT_EQ(f.stat_messages, 0u);
  EXPECT_EQ(f.chunks, 0u);
}

class McapWriterCompression : public ::testing::TestWithParam<fg::McapCompression> {};

TEST_P(McapWriterCompression, GivenMessagesOverSeveralChunksWhenReadBackThenEverythingIsIndexedAndChecksums) {
  const std::string out = writeSample(GetParam(), 2000, 600);
  const auto f = mcap_test::parse(out);
  ASSERT_TRUE(f.errors.empty()) << f.errors.front();
  EXPECT_EQ(f.header_library, "test");
  ASSERT_EQ(f.messages.size(), 600u);
  EXPECT_GT(f.chunks, 5u);
  EXPECT_EQ(f.chunk_indexes, f.chunks);
  EXPECT_EQ(f.stat_chunks, f.chunks);
  EXPECT_EQ(f.stat_messages, 600u);
  EXPECT_EQ(f.stat_schemas, 2);
  EXPECT_EQ(f.stat_channels, 3u);
  EXPECT_EQ(f.stat_channel_counts.at(0), 200u);
  EXPECT_EQ(f.stat_channel_counts.at(1), 200u);
  EXPECT_EQ(f.stat_channel_counts.at(2), 200u);
  EXPECT_EQ(f.stat_start, 1'000'000'000ull);
  EXPECT_EQ(f.stat_end, 1'000'000'000ull + 10'000'000ull * 599 - 5'000'000ull);  // message 599 went back 5 ms
  // Messages in the order written, each with its data and sequence.
  for (int i = 0; i < 600; ++i) {
    EXPECT_EQ(f.messages[i].data, "{\"i\":" + std::to_string(i) + "}");
    EXPECT_EQ(f.messages[i].sequence, static_cast<uint32_t>(i));
    EXPECT_EQ(f.messages[i].log_time, f.messages[i].publish_time);
  }
  // Summary grouped: schemas, channels, statistics, chunk indexes.
  ASSERT_FALSE(f.summary_ops.empty());
  EXPECT_EQ(f.summary_ops.front(), 0x03);
  EXPECT_EQ(f.summary_ops.back(), 0x08);
  EXPECT_EQ(f.summary_channels.size(), 3u);
  EXPECT_EQ(f.summary_channels.at(0).topic, "/a");
  EXPECT_EQ(f.summary_channels.at(0).metadata.at("k"), "v");
  EXPECT_EQ(f.summary_schemas.at(2).name, "b.B");
  EXPECT_EQ(f.summary_schemas.at(2).encoding, "jsonschema");
  EXPECT_EQ(f.channels.at(1).schema, 2);
}

INSTANTIATE_TEST_SUITE_P(AllCompressions, McapWriterCompression,
                         ::testing::Values(fg::McapCompression::kNone, fg::McapCompression::kZstd,
                                           fg::McapCompression::kLz4));

TEST(McapWriter, GivenTheSameCallsWhenWrittenTwiceThenTheBytesAreIdentical) {
  EXPECT_EQ(writeSample(fg::McapCompression::kZstd, 3000, 300), writeSample(fg::McapCompression::kZstd, 3000, 300));
}

TEST(McapWriter, GivenBackgroundChunksWhenWrittenThenTheSameBytesAsInline) {
  for (auto c : {fg::McapCompression::kNone, fg::McapCompression::kZstd, fg::McapCompression::kLz4}) {
    const std::string inline_bytes = writeSample(c, 500, 900, false);
    const std::string background_bytes = writeSample(c, 500, 900, true);
    EXPECT_EQ(inline_bytes, background_bytes);
    const auto f = mcap_test::parse(background_bytes);
    EXPECT_TRUE(f.errors.empty());
    EXPECT_GT(f.chunks, 20u);
  }
}

TEST(McapWriter, GivenAFailingSinkInTheBackgroundWhenWritingThenTheCallerSeesTheError) {
  std::size_t written = 0;
  fg::McapWriterOptions opt;
  opt.background = true;
  opt.chunk_size = 100;
  fg::McapWriter w([&](const uint8_t*, std::size_t n) {
    written += n;
    return written < 2000;
  }, opt);
  ASSERT_TRUE(w.start());
  const uint16_t ch = w.addChannel(0, "/x", "json");
  bool failed = false;
  for (int i = 0; i < 10000 && !failed; ++i) failed = !w.write(ch, 0, i, i, "{\"a\":1}", 7);
  EXPECT_TRUE(failed);
  EXPECT_FALSE(w.finish());
  EXPECT_NE(w.error().find("cannot write"), std::string::npos);
}

TEST(McapWriter, GivenACorruptedByteWhenParsedThenTheChecksumsCatchIt) {
  std::string out = writeSample(fg::McapCompression::kNone, 2000, 60);
  // A byte inside the first chunk's records: after the magic, the header record, the chunk's
  // opcode and length, and its fixed fields (times, size, CRC, empty compression, records length).
  uint64_t header_len = 0;
  for (int i = 7; i >= 0; --i) header_len = (header_len << 8) | static_cast<uint8_t>(out[9 + i]);
  const std::size_t chunk_at = 8 + 9 + header_len;
  ASSERT_EQ(static_cast<uint8_t>(out[chunk_at]), 0x06);
  out[chunk_at + 9 + 8 + 8 + 8 + 4 + 4 + 8 + 40] ^= 0x20;
  const auto f = mcap_test::parse(out);
  ASSERT_FALSE(f.errors.empty());
}

TEST(McapWriter, GivenAFailingSinkWhenWritingThenTheErrorIsReportedAndWritesStop) {
  int calls = 0;
  fg::McapWriter w([&](const uint8_t*, std::size_t) { return ++calls < 2; }, fg::McapWriterOptions{});
  EXPECT_FALSE(w.start());  // the magic was written, the header not
  EXPECT_FALSE(w.ok());
  EXPECT_FALSE(w.finish());
  EXPECT_NE(w.error().find("cannot write"), std::string::npos);
}

TEST(McapWriter, GivenAChannelWithAnUnknownSchemaWhenAddedThenItIsAnError) {
  fg::McapWriter w([](const uint8_t*, std::size_t) { return true; }, fg::McapWriterOptions{});
  ASSERT_TRUE(w.start());
  EXPECT_EQ(w.addChannel(7, "/x", "json"), 0xFFFF);
  EXPECT_FALSE(w.ok());
  EXPECT_NE(w.error().find("schema 7"), std::string::npos);
}

TEST(McapWriter, GivenCompressionNamesWhenParsedThenKnownOnesOnly) {
  fg::McapCompression c = fg::McapCompression::kNone;
  EXPECT_TRUE(fg::parseCompression("lz4", &c));
  EXPECT_EQ(c, fg::McapCompression::kLz4);
  EXPECT_FALSE(fg::parseCompression("gzip", &c));
  EXPECT_EQ(c, fg::McapCompression::kLz4);
  EXPECT_STREQ(fg::toString(fg::McapCompression::kNone), "");
  EXPECT_STREQ(fg::toString(fg::McapCompression::kZstd), "zstd");
}
