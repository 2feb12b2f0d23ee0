#include "ucon/foxglove/mcap_writer.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <limits>

namespace ucon {
namespace foxglove {

namespace {

// Record opcodes of MCAP version 0.
enum Op : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kStatistics = 0x0B,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

// Little-endian integers, length-prefixed strings and maps, as MCAP serialises them.
void putU8(std::string* s, uint8_t v) { s->push_back(static_cast<char>(v)); }
void putU16(std::string* s, uint16_t v) {
  for (int i = 0; i < 2; ++i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void putU32(std::string* s, uint32_t v) {
  for (int i = 0; i < 4; ++i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void putU64(std::string* s, uint64_t v) {
  for (int i = 0; i < 8; ++i) s->push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void putString(std::string* s, const std::string& v) {
  putU32(s, static_cast<uint32_t>(v.size()));
  s->append(v);
}
void putStringMap(std::string* s, const std::map<std::string, std::string>& m) {
  uint32_t len = 0;
  for (const auto& [k, v] : m) len += static_cast<uint32_t>(8 + k.size() + v.size());
  putU32(s, len);
  for (const auto& [k, v] : m) {
    putString(s, k);
    putString(s, v);
  }
}
template <class Map>
void putU16U64Map(std::string* s, const Map& m) {
  putU32(s, static_cast<uint32_t>(m.size() * 10));
  for (const auto& [k, v] : m) {
    putU16(s, k);
    putU64(s, v);
  }
}

}  // namespace

uint32_t crc32(uint32_t crc, const void* data, std::size_t size) {
  const auto* p = static_cast<const Bytef*>(data);
  uLong c = crc;
  while (size > 0) {
    const uInt n = static_cast<uInt>(std::min<std::size_t>(size, std::numeric_limits<uInt>::max()));
    c = ::crc32(c, p, n);
    p += n;
    size -= n;
  }
  return static_cast<uint32_t>(c);
}

const char* toString(McapCompression c) {
  switch (c) {
    case McapCompression::kNone: return "";
    case McapCompression::kZstd: return "zstd";
    case McapCompression::kLz4: return "lz4";
  }
  return "";
}

bool parseCompression(const std::string& name, McapCompression* out) {
  if (name == "none") {
    *out = McapCompression::kNone;
  } else if (name == "zstd") {
    *out = McapCompression::kZstd;
  } else if (name == "lz4") {
    *out = McapCompression::kLz4;
  } else {
    return false;
  }
  return true;
}

/// Compresses chunk records; the zstd context is made once and reused.
class McapWriter::Compressor {
 public:
  Compressor(McapCompression c, int level) : kind_(c), level_(level) {
    if (kind_ == McapCompression::kZstd) zstd_ = ZSTD_createCCtx();
  }
  ~Compressor() {
    if (zstd_) ZSTD_freeCCtx(zstd_);
  }
  Compressor(const Compressor&) = delete;
  Compressor& operator=(const Compressor&) = delete;

  /// Fills *out with the compressed `in`; false with *error on failure.
  bool compress(const std::string& in, std::string* out, std::string* error) {
    switch (kind_) {
      case McapCompression::kNone:
        return true;  // the caller writes `in` itself
      case McapCompression::kZstd: {
        if (!zstd_) {
          *error = "zstd: cannot create a compression context";
          return false;
        }
        out->resize(ZSTD_compressBound(in.size()));
        const std::size_t n = ZSTD_compressCCtx(zstd_, &(*out)[0], out->size(), in.data(), in.size(), level_);
        if (ZSTD_isError(n)) {
          *error = std::string("zstd: ") + ZSTD_getErrorName(n);
          return false;
        }
        out->resize(n);
        return true;
      }
      case McapCompression::kLz4: {
        LZ4F_preferences_t prefs = LZ4F_INIT_PREFERENCES;
        prefs.frameInfo.contentSize = in.size();
        out->resize(LZ4F_compressFrameBound(in.size(), &prefs));
        const std::size_t n = LZ4F_compressFrame(&(*out)[0], out->size(), in.data(), in.size(), &prefs);
        if (LZ4F_isError(n)) {
          *error = std::string("lz4: ") + LZ4F_getErrorName(n);
          return false;
        }
        out->resize(n);
        return true;
      }
    }
    return false;
  }

 private:
  McapCompression kind_;
  int level_;
  ZSTD_CCtx* zstd_ = nullptr;
};

McapWriter::McapWriter(ByteSink sink, McapWriterOptions options)
    : sink_(std::move(sink)), options_(std::move(options)) {
  if (options_.chunk_size < 1) options_.chunk_size = 1;
  compressor_ = std::make_unique<Compressor>(options_.compression, options_.zstd_level);
  open_.records.reserve(options_.chunk_size + (options_.chunk_size >> 3));
}

McapWriter::~McapWriter() { stopWorker(); }

void McapWriter::stopWorker() {
  if (!worker_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  worker_.join();
}

bool McapWriter::ok() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_.empty();
}

std::string McapWriter::error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

McapStats McapWriter::stats() const {
  McapStats s = counts_;
  std::lock_guard<std::mutex> lock(mutex_);
  s.bytes = bytes_;
  s.chunks = chunks_;
  s.uncompressed_bytes = uncompressed_bytes_;
  return s;
}

bool McapWriter::fail(const std::string& what) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (error_.empty()) error_ = what;
  return false;
}

bool McapWriter::emit(const void* data, std::size_t size) {
  if (size == 0) return true;
  if (!sink_(static_cast<const uint8_t*>(data), size)) return fail("cannot write the output");
  if (in_data_section_) data_crc_ = crc32(data_crc_, data, size);
  position_ += size;
  std::lock_guard<std::mutex> lock(mutex_);
  bytes_ += size;
  return true;
}

bool McapWriter::emitRecord(uint8_t opcode, const std::string& body) {
  std::string head;
  putU8(&head, opcode);
  putU64(&head, body.size());
  return emit(head.data(), head.size()) && emit(body.data(), body.size());
}

bool McapWriter::start() {
  if (started_) return fail("start() called twice");
  started_ = true;
  std::string body;
  putString(&body, options_.profile);
  putString(&body, options_.library);
  const bool written = emit(kMagic, sizeof(kMagic)) && emitRecord(kHeader, body);
  if (written && options_.background) worker_ = std::thread([this] { workerLoop(); });
  return written;
}

uint16_t McapWriter::addSchema(const std::string& name, const std::string& encoding, const std::string& data) {
  if (!ok()) return 0;
  if (schemas_.size() >= 0xFFFF) {
    fail("more than 65535 schemas");
    return 0;
  }
  schemas_.push_back(Schema{name, encoding, data, false});
  return static_cast<uint16_t>(schemas_.size());
}

uint16_t McapWriter::addChannel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                                const std::map<std::string, std::string>& metadata) {
  if (!ok()) return 0xFFFF;
  if (schema_id > schemas_.size()) {
    fail("channel " + topic + " names schema " + std::to_string(schema_id) + ", which does not exist");
    return 0xFFFF;
  }
  if (channels_.size() >= 0xFFFF) {
    fail("more than 65535 channels");
    return 0xFFFF;
  }
  channels_.push_back(Channel{schema_id, topic, message_encoding, metadata, false});
  return static_cast<uint16_t>(channels_.size() - 1);
}

void McapWriter::schemaRecord(uint16_t id, std::string* out) const {
  const Schema& s = schemas_[id - 1];
  putU16(out, id);
  putString(out, s.name);
  putString(out, s.encoding);
  putString(out, s.data);
}

void McapWriter::channelRecord(uint16_t id, std::string* out) const {
  const Channel& c = channels_[id];
  putU16(out, id);
  putU16(out, c.schema_id);
  putString(out, c.topic);
  putString(out, c.encoding);
  putStringMap(out, c.metadata);
}

void McapWriter::appendToChunk(uint8_t opcode, const std::string& body) {
  putU8(&open_.records, opcode);
  putU64(&open_.records, body.size());
  open_.records.append(body);
}

bool McapWriter::write(uint16_t channel_id, uint32_t sequence, uint64_t log_time, uint64_t publish_time,
                       const void* data, std::size_t size) {
  if (!ok()) return false;
  if (!started_ || finished_) return fail("write() outside start() .. finish()");
  if (channel_id >= channels_.size()) return fail("write() on unknown channel " + std::to_string(channel_id));
  Channel& ch = channels_[channel_id];
  if (!ch.written) {
    if (ch.schema_id != 0 && !schemas_[ch.schema_id - 1].written) {
      scratch_.clear();
      schemaRecord(ch.schema_id, &scratch_);
      appendToChunk(kSchema, scratch_);
      schemas_[ch.schema_id - 1].written = true;
      ++counts_.schemas;
    }
    scratch_.clear();
    channelRecord(channel_id, &scratch_);
    appendToChunk(kChannel, scratch_);
    ch.written = true;
    ++counts_.channels;
  }
  std::string& r = open_.records;
  open_.index[channel_id].emplace_back(log_time, r.size());
  putU8(&r, kMessage);
  putU64(&r, 2 + 4 + 8 + 8 + size);
  putU16(&r, channel_id);
  putU32(&r, sequence);
  putU64(&r, log_time);
  putU64(&r, publish_time);
  if (size > 0) r.append(static_cast<const char*>(data), size);

  if (!open_.has_messages) {
    open_.start = open_.end = log_time;
    open_.has_messages = true;
  }
  open_.start = std::min(open_.start, log_time);
  open_.end = std::max(open_.end, log_time);
  if (counts_.messages == 0) counts_.start_time = counts_.end_time = log_time;
  counts_.start_time = std::min(counts_.start_time, log_time);
  counts_.end_time = std::max(counts_.end_time, log_time);
  ++counts_.messages;
  ++counts_.channel_messages[channel_id];

  if (r.size() >= options_.chunk_size) return closeChunk();
  return true;
}

bool McapWriter::closeChunk() {
  if (open_.records.empty()) return true;
  if (!worker_.joinable()) {
    const bool written = writeChunk(open_);
    open_.records.clear();
    open_.index.clear();
    open_.has_messages = false;
    return written;
  }
  // Hand the chunk to the worker (waiting while two are queued) and start the next in a
  // buffer it gave back.
  std::string next;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait(lock, [this] { return queue_.size() < 2 || !error_.empty(); });
    if (!error_.empty()) return false;
    queue_.push_back(std::move(open_));
    if (!spare_.empty()) {
      next = std::move(spare_.back());
      spare_.pop_back();
    }
  }
  cv_.notify_all();
  open_ = Chunk();
  next.clear();
  if (next.capacity() < options_.chunk_size) next.reserve(options_.chunk_size + (options_.chunk_size >> 3));
  open_.records = std::move(next);
  return true;
}

void McapWriter::workerLoop() {
  for (;;) {
    Chunk c;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return !queue_.empty() || stopping_; });
      if (queue_.empty()) return;  // stopping, nothing left
      c = std::move(queue_.front());
      queue_.pop_front();
    }
    const bool written = writeChunk(c);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      c.records.clear();
      spare_.push_back(std::move(c.records));
    }
    cv_.notify_all();
    if (!written) return;
  }
}

bool McapWriter::writeChunk(Chunk& c) {
  const uint32_t crc = crc32(0, c.records.data(), c.records.size());
  std::string err;
  if (!compressor_->compress(c.records, &compressed_, &err)) return fail(err);
  const std::string& payload = options_.compression == McapCompression::kNone ? c.records : compressed_;
  const std::string compression = toString(options_.compression);

  ChunkIndex ci;
  ci.start_time = c.has_messages ? c.start : 0;
  ci.end_time = c.has_messages ? c.end : 0;
  ci.offset = position_;
  ci.compressed_size = payload.size();
  ci.uncompressed_size = c.records.size();

  std::string head;
  putU64(&head, ci.start_time);
  putU64(&head, ci.end_time);
  putU64(&head, c.records.size());
  putU32(&head, crc);
  putString(&head, compression);
  putU64(&head, payload.size());
  const uint64_t body_size = head.size() + payload.size();
  std::string prefix;
  putU8(&prefix, kChunk);
  putU64(&prefix, body_size);
  if (!emit(prefix.data(), prefix.size()) || !emit(head.data(), head.size()) ||
      !emit(payload.data(), payload.size())) {
    return false;
  }
  ci.length = prefix.size() + body_size;

  // One Message Index per channel of the chunk, entries in log-time order (stable, so equal
  // times keep the order they were written in).
  const uint64_t index_start = position_;
  for (auto& [channel, entries] : c.index) {
    std::stable_sort(entries.begin(), entries.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    index_scratch_.clear();
    putU16(&index_scratch_, channel);
    putU32(&index_scratch_, static_cast<uint32_t>(entries.size() * 16));
    for (const auto& [t, off] : entries) {
      putU64(&index_scratch_, t);
      putU64(&index_scratch_, off);
    }
    ci.index_offsets[channel] = position_;
    if (!emitRecord(kMessageIndex, index_scratch_)) return false;
  }
  ci.index_length = position_ - index_start;
  chunk_indexes_.push_back(std::move(ci));
  std::lock_guard<std::mutex> lock(mutex_);
  uncompressed_bytes_ += c.records.size();
  ++chunks_;
  return true;
}

bool McapWriter::finish() {
  if (!ok()) {
    stopWorker();
    return false;
  }
  if (!started_ || finished_) return fail("finish() without start(), or twice");
  finished_ = true;
  const bool closed = closeChunk();
  stopWorker();  // the queued chunks are written first
  if (!closed || !ok()) return false;
  const McapStats stats = this->stats();

  std::string body;
  putU32(&body, data_crc_);
  if (!emitRecord(kDataEnd, body)) return false;
  in_data_section_ = false;

  // Summary: every group of records of one opcode together, each group's place remembered
  // for the Summary Offset records. Only schemas and channels that a message used.
  const uint64_t summary_start = position_;
  uint32_t summary_crc = 0;
  std::string summary;
  struct Group {
    uint8_t opcode;
    uint64_t start, length;
  };
  std::vector<Group> groups;
  auto group = [&](uint8_t opcode, const std::function<void()>& records) {
    const std::size_t before = summary.size();
    records();
    if (summary.size() > before) groups.push_back({opcode, summary_start + before, summary.size() - before});
  };
  auto record = [&](uint8_t opcode, const std::string& b) {
    putU8(&summary, opcode);
    putU64(&summary, b.size());
    summary.append(b);
  };
  group(kSchema, [&] {
    for (std::size_t i = 0; i < schemas_.size(); ++i) {
      if (!schemas_[i].written) continue;
      body.clear();
      schemaRecord(static_cast<uint16_t>(i + 1), &body);
      record(kSchema, body);
    }
  });
  group(kChannel, [&] {
    for (std::size_t i = 0; i < channels_.size(); ++i) {
      if (!channels_[i].written) continue;
      body.clear();
      channelRecord(static_cast<uint16_t>(i), &body);
      record(kChannel, body);
    }
  });
  group(kStatistics, [&] {
    body.clear();
    putU64(&body, stats.messages);
    putU16(&body, stats.schemas);
    putU32(&body, stats.channels);
    putU32(&body, 0);  // attachments
    putU32(&body, 0);  // metadata
    putU32(&body, stats.chunks);
    putU64(&body, stats.start_time);
    putU64(&body, stats.end_time);
    putU16U64Map(&body, stats.channel_messages);
    record(kStatistics, body);
  });
  group(kChunkIndex, [&] {
    for (const auto& ci : chunk_indexes_) {
      body.clear();
      putU64(&body, ci.start_time);
      putU64(&body, ci.end_time);
      putU64(&body, ci.offset);
      putU64(&body, ci.length);
      putU16U64Map(&body, ci.index_offsets);
      putU64(&body, ci.index_length);
      putString(&body, toString(options_.compression));
      putU64(&body, ci.compressed_size);
      putU64(&body, ci.uncompressed_size);
      record(kChunkIndex, body);
    }
  });
  const uint64_t summary_offset_start = summary_start + summary.size();
  for (const auto& g : groups) {
    body.clear();
    putU8(&body, g.opcode);
    putU64(&body, g.start);
    putU64(&body, g.length);
    record(kSummaryOffset, body);
  }
  // Footer: its CRC covers the summary, the summary offsets and the footer up to the CRC.
  std::string footer;
  putU8(&footer, kFooter);
  putU64(&footer, 8 + 8 + 4);
  putU64(&footer, summary_start);
  putU64(&footer, summary_offset_start);
  summary_crc = crc32(summary_crc, summary.data(), summary.size());
  summary_crc = crc32(summary_crc, footer.data(), footer.size());
  putU32(&footer, summary_crc);
  return emit(summary.data(), summary.size()) && emit(footer.data(), footer.size()) &&
         emit(kMagic, sizeof(kMagic));
}

}  // namespace foxglove
}  // namespace ucon
