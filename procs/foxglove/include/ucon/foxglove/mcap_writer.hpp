#pragma once
/// @file mcap_writer.hpp
/// Writer of MCAP files (format version 0, the one Foxglove reads): leading magic, Header,
/// a data section of Chunks (zstd, lz4 frame or uncompressed), each followed by one Message
/// Index per channel in it, Data End with the CRC-32 of the data section, then a Summary
/// section grouped by opcode (Schemas, Channels, Statistics, Chunk Indexes), Summary Offsets
/// pointing at each group, the Footer with the CRC-32 of the summary, and the trailing magic.
/// Schema and Channel records go into the chunk of their channel's first message and are
/// repeated in the summary, so that a reader can seek by time from the summary alone.
///
/// The writer holds no file: it hands its bytes, in order, to a sink. Errors are values
/// (ok(), error()); nothing is printed. Same calls in, same bytes out.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ucon {
namespace foxglove {

/// CRC-32 (ISO-HDLC, the zlib/PNG one) that MCAP uses, continued from `crc` (0 to start).
uint32_t crc32(uint32_t crc, const void* data, std::size_t size);

enum class McapCompression { kNone, kZstd, kLz4 };
/// "" (none), "zstd", "lz4": the names MCAP stores in a chunk.
const char* toString(McapCompression c);
/// Parses "none", "zstd" or "lz4"; false (and `out` unchanged) otherwise.
bool parseCompression(const std::string& name, McapCompression* out);

struct McapWriterOptions {
  McapCompression compression = McapCompression::kZstd;
  int zstd_level = 1;                    ///< zstd level, 1 (fastest) .. 19 (smallest, slowest)
  std::size_t chunk_size = 4u << 20;     ///< a chunk is closed once its records reach this [bytes], >= 1
  std::string profile;                   ///< MCAP Header profile ("" = none)
  std::string library = "ucon";          ///< MCAP Header library (writer name and version)
  /// Compress and write each chunk on a thread of its own while the caller fills the next
  /// (at most two chunks wait). Same bytes either way.
  bool background = false;
};

/// What has been written so far.
struct McapStats {
  uint64_t messages = 0;
  uint32_t chunks = 0;
  uint16_t schemas = 0;          ///< schemas used by a written message
  uint32_t channels = 0;         ///< channels with a written message
  uint64_t bytes = 0;            ///< bytes handed to the sink
  uint64_t uncompressed_bytes = 0;  ///< chunk records before compression
  uint64_t start_time = 0;       ///< earliest log time [ns] (0 without messages)
  uint64_t end_time = 0;         ///< latest log time [ns]
  std::map<uint16_t, uint64_t> channel_messages;  ///< messages per channel id
};

/// Receives the file's bytes in order; returns false when they cannot be written.
using ByteSink = std::function<bool(const uint8_t* data, std::size_t size)>;

class McapWriter {
 public:
  McapWriter(ByteSink sink, McapWriterOptions options);
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// Writes the magic and the Header. Call once, before anything else.
  bool start();

  /// Registers a schema; returns its id (1, 2, ...), or 0 after an error.
  uint16_t addSchema(const std::string& name, const std::string& encoding, const std::string& data);
  /// Registers a channel on `schema_id` (0 = no schema); returns its id (0, 1, ...), or
  /// 0xFFFF after an error (bad schema id, more than 65535 channels).
  uint16_t addChannel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                      const std::map<std::string, std::string>& metadata = {});

  /// Appends one message. `log_time` and `publish_time` in ns. False after an error.
  bool write(uint16_t channel_id, uint32_t sequence, uint64_t log_time, uint64_t publish_time,
             const void* data, std::size_t size);

  /// Closes the open chunk, writes Data End, the summary, the Footer and the magic. After it
  /// the file is complete; further calls fail.
  bool finish();

  bool ok() const;
  std::string error() const;
  /// Counts so far (bytes and chunks include the chunks written up to now).
  McapStats stats() const;

 private:
  struct Schema {
    std::string name, encoding, data;
    bool written = false;  // in a chunk already
  };
  struct Channel {
    uint16_t schema_id = 0;
    std::string topic, encoding;
    std::map<std::string, std::string> metadata;
    bool written = false;
  };
  struct ChunkIndex {
    uint64_t start_time, end_time, offset, length;
    std::map<uint16_t, uint64_t> index_offsets;
    uint64_t index_length, compressed_size, uncompressed_size;
  };
  /// A closed chunk: its records and, per channel, (log time, offset in the records).
  struct Chunk {
    std::string records;
    std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> index;
    uint64_t start = 0, end = 0;
    bool has_messages = false;
  };
  class Compressor;

  bool fail(const std::string& what);
  bool emit(const void* data, std::size_t size);
  bool emitRecord(uint8_t opcode, const std::string& body);
  void schemaRecord(uint16_t id, std::string* out) const;
  void channelRecord(uint16_t id, std::string* out) const;
  void appendToChunk(uint8_t opcode, const std::string& body);
  bool closeChunk();
  bool writeChunk(Chunk& c);  // CRC, compression, the Chunk record and its Message Indexes
  void workerLoop();
  void stopWorker();

  ByteSink sink_;
  McapWriterOptions options_;
  std::unique_ptr<Compressor> compressor_;
  bool started_ = false, finished_ = false;

  // Caller's thread: registrations, message counts, the open chunk.
  std::vector<Schema> schemas_;    // id = index + 1
  std::vector<Channel> channels_;  // id = index
  McapStats counts_;
  Chunk open_;
  std::string scratch_;

  // Output side (the worker's between start() and finish() when options_.background).
  uint64_t position_ = 0;
  uint32_t data_crc_ = 0;
  bool in_data_section_ = true;
  uint64_t bytes_ = 0, uncompressed_bytes_ = 0;
  uint32_t chunks_ = 0;
  std::vector<ChunkIndex> chunk_indexes_;
  std::string compressed_, index_scratch_;

  // Hand-over between the two.
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Chunk> queue_;
  std::vector<std::string> spare_;  // record buffers to reuse
  bool stopping_ = false;
  std::string error_;
  std::thread worker_;
};

}  // namespace foxglove
}  // namespace ucon
