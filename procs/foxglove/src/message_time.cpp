#include "ucon/foxglove/message_time.hpp"

#include "ucon/foxglove/lcm_json.hpp"

namespace ucon {
namespace foxglove {

std::optional<int64_t> MessageClock::ownTime(const LcmTypeInfo& type, const void* data, std::size_t size) {
  if (!type.has_message_time) return std::nullopt;
  const int64_t t = encodedUtime(data, size);
  if (t <= 0) return std::nullopt;
  return t;
}

std::optional<int64_t> MessageClock::timeOf(const LcmTypeInfo& type, const void* data, std::size_t size) {
  if (const auto t = ownTime(type, data, size)) {
    now_ = *t;
    started_ = true;
    return t;
  }
  if (started_) return now_;
  return std::nullopt;
}

}  // namespace foxglove
}  // namespace ucon
