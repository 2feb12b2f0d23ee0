#pragma once
/// @file pcap_reader.hpp
/// Reads a packet capture (pcap or pcapng, as tcpdump writes it) with libpcap, frame by frame,
/// with nanosecond timestamps. Process side (file I/O); the frames' UDP datagrams are found by
/// extractUdp().

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace ucon {
namespace lidar_driver {

class PcapReader {
 public:
  /// Opens `path`; nullptr and `error` (naming the file) on failure.
  static std::unique_ptr<PcapReader> open(const std::string& path, std::string* error);
  ~PcapReader();
  PcapReader(const PcapReader&) = delete;
  PcapReader& operator=(const PcapReader&) = delete;

  /// pcap link type of the capture (LINKTYPE_*).
  int linkType() const { return linktype_; }

  struct Frame {
    int64_t time_ns = 0;           ///< capture time, CLOCK_REALTIME of the capturing host [ns]
    const uint8_t* data = nullptr;  ///< valid until the next call
    std::size_t caplen = 0;        ///< captured bytes
    std::size_t wirelen = 0;       ///< bytes on the wire (> caplen: cut by the snap length)
  };
  /// 1: a frame; 0: end of the capture; -1: a read error (`error` says which).
  int next(Frame& frame, std::string* error);

 private:
  explicit PcapReader(void* handle);
  void* handle_;  // pcap_t
  int linktype_ = 0;
  bool nano_ = true;
};

}  // namespace lidar_driver
}  // namespace ucon
