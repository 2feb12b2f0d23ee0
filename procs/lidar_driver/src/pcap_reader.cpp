#include "ucon/lidar_driver/pcap_reader.hpp"

#include <pcap/pcap.h>

namespace ucon {
namespace lidar_driver {

std::unique_ptr<PcapReader> PcapReader::open(const std::string& path, std::string* error) {
  char errbuf[PCAP_ERRBUF_SIZE] = {0};
  pcap_t* p = pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, errbuf);
  if (p == nullptr) {
    if (error) *error = "cannot read capture " + path + ": " + errbuf;
    return nullptr;
  }
  std::unique_ptr<PcapReader> r(new PcapReader(p));
  r->linktype_ = pcap_datalink(p);
  r->nano_ = pcap_get_tstamp_precision(p) == PCAP_TSTAMP_PRECISION_NANO;
  return r;
}

PcapReader::PcapReader(void* handle) : handle_(handle) {}

PcapReader::~PcapReader() { pcap_close(static_cast<pcap_t*>(handle_)); }

int PcapReader::next(Frame& frame, std::string* error) {
  pcap_pkthdr* h = nullptr;
  const u_char* data = nullptr;
  const int rc = pcap_next_ex(static_cast<pcap_t*>(handle_), &h, &data);
  if (rc == PCAP_ERROR_BREAK) return 0;  // end of file
  if (rc != 1) {
    if (error) *error = pcap_geterr(static_cast<pcap_t*>(handle_));
    return -1;
  }
  const int64_t sub = static_cast<int64_t>(h->ts.tv_usec);
  frame.time_ns = static_cast<int64_t>(h->ts.tv_sec) * 1'000'000'000 + (nano_ ? sub : sub * 1000);
  frame.data = data;
  frame.caplen = h->caplen;
  frame.wirelen = h->len;
  return 1;
}

}  // namespace lidar_driver
}  // namespace ucon
