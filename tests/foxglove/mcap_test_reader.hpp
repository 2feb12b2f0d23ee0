#pragma once
// A small MCAP parser for the tests, written from the format description independently of
// the writer: it walks the file record by record, decompresses chunks, and checks every
// length, offset and CRC it meets. Failures are collected as text (empty = the file is valid).

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace mcap_test {

struct Record {
  uint8_t op = 0;
  uint64_t offset = 0;  // of the opcode byte (in the file, or in the chunk's records)
  std::string body;
};

struct Message {
  uint16_t channel = 0;
  uint32_t sequence = 0;
  uint64_t log_time = 0, publish_time = 0;
  std::string data;
};

struct Channel {
  uint16_t id = 0, schema = 0;
  std::string topic, encoding;
  std::map<std::string, std::string> metadata;
};

struct Schema {
  uint16_t id = 0;
  std::string name, encoding, data;
};

struct File {
  std::vector<std::string> errors;
  std::string header_profile, header_library;
  std::vector<Message> messages;           // in file order
  std::map<uint16_t, Channel> channels;    // from the data section
  std::map<uint16_t, Schema> schemas;
  std::map<uint16_t, Channel> summary_channels;
  std::map<uint16_t, Schema> summary_schemas;
  std::vector<uint8_t> summary_ops;        // opcodes of the summary section, in order
  uint64_t chunks = 0, chunk_indexes = 0;
  uint64_t stat_messages = 0, stat_chunks = 0, stat_start = 0, stat_end = 0;
  uint32_t stat_channels = 0;
  uint16_t stat_schemas = 0;
  std::map<uint16_t, uint64_t> stat_channel_counts;
  bool has_statistics = false;
};

class Cursor {
 public:
  Cursor(const std::string& s, std::size_t pos = 0, std::size_t end = std::string::npos)
      : s_(s), pos_(pos), end_(end == std::string::npos ? s.size() : end) {}
  bool ok() const { return ok_; }
  std::size_t pos() const { return pos_; }
  bool atEnd() const { return pos_ >= end_; }
  uint64_t le(int n) {
    if (pos_ + n > end_) {
      ok_ = false;
      return 0;
    }
    uint64_t v = 0;
    for (int i = n - 1; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(s_[pos_ + i]);
    pos_ += n;
    return v;
  }
  std::string bytes(uint64_t n) {
    if (pos_ + n > end_) {
      ok_ = false;
      return {};
    }
    std::string out = s_.substr(pos_, n);
    pos_ += n;
    return out;
  }
  std::string str() { return bytes(le(4)); }

 private:
  const std::string& s_;
  std::size_t pos_, end_;
  bool ok_ = true;
};

inline uint32_t crc(const std::string& s, std::size_t from, std::size_t to) {
  return static_cast<uint32_t>(::crc32(0, reinterpret_cast<const Bytef*>(s.data() + from), static_cast<uInt>(to - from)));
}

inline std::map<std::string, std::string> stringMap(Cursor& c) {
  std::map<std::string, std::string> m;
  const uint64_t len = c.le(4);
  const std::size_t end = c.pos() + len;
  while (c.ok() && c.pos() < end) {
    std::string k = c.str();
    m[k] = c.str();
  }
  return m;
}

inline Channel parseChannel(const std::string& body) {
  Cursor c(body);
  Channel ch;
  ch.id = static_cast<uint16_t>(c.le(2));
  ch.schema = static_cast<uint16_t>(c.le(2));
  ch.topic = c.str();
  ch.encoding = c.str();
  ch.metadata = stringMap(c);
  return ch;
}

inline Schema parseSchema(const std::string& body) {
  Cursor c(body);
  Schema s;
  s.id = static_cast<uint16_t>(c.le(2));
  s.name = c.str();
  s.encoding = c.str();
  s.data = c.str();
  return s;
}

inline std::string decompress(const std::string& compression, const std::string& in, uint64_t size, std::string* err) {
  std::string out(size, '\0');
  if (compression.empty()) return in;
  if (compression == "zstd") {
    const std::size_t n = ZSTD_decompress(&out[0], out.size(), in.data(), in.size());
    if (ZSTD_isError(n) || n != size) *err = "zstd chunk does not decompress to its size";
    return out;
  }
  if (compression == "lz4") {
    LZ4F_dctx* ctx = nullptr;
    LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION);
    std::size_t dst = out.size(), src = in.size();
    const std::size_t r = LZ4F_decompress(ctx, &out[0], &dst, in.data(), &src, nullptr);
    LZ4F_freeDecompressionContext(ctx);
    if (LZ4F_isError(r) || dst != size || src != in.size()) *err = "lz4 chunk does not decompress to its size";
    return out;
  }
  *err = "unknown compression " + compression;
  return {};
}

// Records of one sequence (file section or chunk).
inline std::vector<Record> records(const std::string& s, std::size_t from, std::size_t to, std::vector<std::string>* errors) {
  std::vector<Record> out;
  Cursor c(s, from, to);
  while (!c.atEnd()) {
    Record r;
    r.offset = c.pos();
    r.op = static_cast<uint8_t>(c.le(1));
    const uint64_t len = c.le(8);
    r.body = c.bytes(len);
    if (!c.ok()) {
      errors->push_back("record at " + std::to_string(r.offset) + " runs past its section");
      break;
    }
    out.push_back(std::move(r));
  }
  return out;
}

inline File parse(const std::string& f) {
  File out;
  auto& E = out.errors;
  static const std::string kMagic("\x89MCAP0\r\n", 8);
  if (f.size() < 8 + 9 + 20 + 8 || f.compare(0, 8, kMagic) != 0 || f.compare(f.size() - 8, 8, kMagic) != 0) {
    E.push_back("magic missing at the start or the end");
    return out;
  }
  // Footer: fixed size before the trailing magic.
  const std::size_t footer_at = f.size() - 8 - (1 + 8 + 20);
  Cursor fc(f, footer_at);
  if (fc.le(1) != 0x02 || fc.le(8) != 20) E.push_back("footer record not where it belongs");
  const uint64_t summary_start = fc.le(8), summary_offset_start = fc.le(8);
  const uint32_t summary_crc = static_cast<uint32_t>(fc.le(4));
  if (summary_start != 0 && summary_crc != 0 && summary_crc != crc(f, summary_start, footer_at + 1 + 8 + 16))
    E.push_back("footer summary CRC is wrong");

  // Data section, from the header to Data End.
  const auto recs = records(f, 8, summary_start ? summary_start : footer_at, &E);
  if (recs.empty() || recs[0].op != 0x01) {
    E.push_back("first record is not the Header");
    return out;
  }
  {
    Cursor h(recs[0].body);
    out.header_profile = h.str();
    out.header_library = h.str();
  }
  bool data_end = false;
  struct PendingIndex {
    std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> entries;  // from the chunk itself
    uint64_t chunk_offset = 0;
  } pending;
  std::map<uint64_t, std::string> chunk_payloads;  // chunk file offset -> uncompressed records
  std::map<uint64_t, uint64_t> message_index_at;   // file offset of a message index -> its channel
  for (std::size_t i = 1; i < recs.size(); ++i) {
    const Record& r = recs[i];
    if (data_end) {
      E.push_back("record after Data End in the data section");
      break;
    }
    switch (r.op) {
      case 0x06: {  // Chunk
        ++out.chunks;
        Cursor c(r.body);
        const uint64_t start = c.le(8), end = c.le(8), usize = c.le(8);
        const uint32_t ucrc = static_cast<uint32_t>(c.le(4));
        const std::string comp = c.str();
        const std::string payload = c.bytes(c.le(8));
        if (!c.ok()) {
          E.push_back("chunk fields run past the record");
          break;
        }
        std::string err;
        const std::string records_bytes = decompress(comp, payload, usize, &err);
        if (!err.empty()) E.push_back(err);
        if (ucrc != 0 && ucrc != crc(records_bytes, 0, records_bytes.size())) E.push_back("chunk CRC is wrong");
        chunk_payloads[r.offset] = records_bytes;
        uint64_t lo = UINT64_MAX, hi = 0;
        for (const auto& cr : records(records_bytes, 0, records_bytes.size(), &E)) {
          if (cr.op == 0x03) {
            const Schema s = parseSchema(cr.body);
            out.schemas[s.id] = s;
          } else if (cr.op == 0x04) {
            const Channel ch = parseChannel(cr.body);
            if (ch.schema != 0 && !out.schemas.count(ch.schema)) E.push_back("channel before its schema");
            out.channels[ch.id] = ch;
          } else if (cr.op == 0x05) {
            Cursor m(cr.body);
            Message msg;
            msg.channel = static_cast<uint16_t>(m.le(2));
            msg.sequence = static_cast<uint32_t>(m.le(4));
            msg.log_time = m.le(8);
            msg.publish_time = m.le(8);
            msg.data = cr.body.substr(22);
            if (!out.channels.count(msg.channel)) E.push_back("message before its channel");
            lo = std::min(lo, msg.log_time);
            hi = std::max(hi, msg.log_time);
            pending.entries[msg.channel].emplace_back(msg.log_time, cr.offset);
            out.messages.push_back(std::move(msg));
          } else {
            E.push_back("unexpected record in a chunk: op " + std::to_string(cr.op));
          }
        }
        if (lo != UINT64_MAX && (lo != start || hi != end)) E.push_back("chunk start/end times are wrong");
        pending.chunk_offset = r.offset;
        break;
      }
      case 0x07: {  // Message Index: must list exactly the chunk's messages of its channel
        Cursor c(r.body);
        const uint16_t ch = static_cast<uint16_t>(c.le(2));
        const uint64_t len = c.le(4);
        std::vector<std::pair<uint64_t, uint64_t>> entries;
        for (uint64_t k = 0; k < len / 16; ++k) {
          const uint64_t t = c.le(8);
          entries.emplace_back(t, c.le(8));
        }
        auto expected = pending.entries[ch];
        std::stable_sort(expected.begin(), expected.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });
        if (entries != expected) E.push_back("message index of channel " + std::to_string(ch) + " is wrong");
        message_index_at[r.offset] = ch;
        pending.entries.erase(ch);
        break;
      }
      case 0x0F: {
        data_end = true;
        Cursor c(r.body);
        const uint32_t dcrc = static_cast<uint32_t>(c.le(4));
        if (dcrc != 0 && dcrc != crc(f, 0, r.offset)) E.push_back("data section CRC is wrong");
        break;
      }
      default:
        E.push_back("unexpected record in the data section: op " + std::to_string(r.op));
    }
  }
  if (!data_end) E.push_back("no Data End record");
  if (summary_start == 0) return out;

  // Summary and summary offsets.
  const auto summary = records(f, summary_start, summary_offset_start ? summary_offset_start : footer_at, &E);
  std::map<uint8_t, std::pair<uint64_t, uint64_t>> groups;  // op -> (start, length)
  for (const auto& r : summary) {
    if (!out.summary_ops.empty() && out.summary_ops.back() != r.op) {
      for (uint8_t seen : out.summary_ops)
        if (seen == r.op) E.push_back("summary records are not grouped by opcode");
    }
    out.summary_ops.push_back(r.op);
    auto& g = groups[r.op];
    if (g.second == 0) g.first = r.offset;
    g.second += 9 + r.body.size();
    if (r.op == 0x03) {
      const Schema s = parseSchema(r.body);
      out.summary_schemas[s.id] = s;
    } else if (r.op == 0x04) {
      const Channel ch = parseChannel(r.body);
      out.summary_channels[ch.id] = ch;
    } else if (r.op == 0x0B) {
      out.has_statistics = true;
      Cursor c(r.body);
      out.stat_messages = c.le(8);
      out.stat_schemas = static_cast<uint16_t>(c.le(2));
      out.stat_channels = static_cast<uint32_t>(c.le(4));
      c.le(4);
      c.le(4);
      out.stat_chunks = c.le(4);
      out.stat_start = c.le(8);
      out.stat_end = c.le(8);
      const uint64_t len = c.le(4);
      for (uint64_t k = 0; k < len / 10; ++k) {
        const uint16_t id = static_cast<uint16_t>(c.le(2));
        out.stat_channel_counts[id] = c.le(8);
      }
    } else if (r.op == 0x08) {
      ++out.chunk_indexes;
      Cursor c(r.body);
      c.le(8);
      c.le(8);
      const uint64_t off = c.le(8), len = c.le(8);
      if (!chunk_payloads.count(off) || f[off] != 0x06) {
        E.push_back("chunk index points at no chunk");
        continue;
      }
      uint64_t body_len = 0;
      std::memcpy(&body_len, f.data() + off + 1, 8);
      if (len != 9 + body_len) E.push_back("chunk index length is wrong");
      const uint64_t map_len = c.le(4);
      uint64_t indexes = 0;
      for (uint64_t k = 0; k < map_len / 10; ++k) {
        const uint16_t ch = static_cast<uint16_t>(c.le(2));
        const uint64_t at = c.le(8);
        if (!message_index_at.count(at) || message_index_at[at] != ch) E.push_back("message index offset is wrong");
        ++indexes;
      }
      const uint64_t index_len = c.le(8);
      if (indexes > 0 && f[off + len] != 0x07) E.push_back("message indexes do not follow their chunk");
      if (index_len == 0 && indexes > 0) E.push_back("message index length is 0");
    } else {
      E.push_back("unexpected record in the summary: op " + std::to_string(r.op));
    }
  }
  if (summary_offset_start) {
    const auto offsets = records(f, summary_offset_start, footer_at, &E);
    std::map<uint8_t, std::pair<uint64_t, uint64_t>> listed;
    for (const auto& r : offsets) {
      if (r.op != 0x0E) {
        E.push_back("non-offset record in the summary offset section");
        continue;
      }
      Cursor c(r.body);
      const uint8_t op = static_cast<uint8_t>(c.le(1));
      const uint64_t start = c.le(8);
      listed[op] = {start, c.le(8)};
    }
    if (listed != groups) E.push_back("summary offsets do not match the summary's groups");
  }
  return out;
}

}  // namespace mcap_test
