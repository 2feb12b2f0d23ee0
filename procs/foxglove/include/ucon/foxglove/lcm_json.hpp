#pragma once
/// @file lcm_json.hpp
/// The JSON encoding of every ucon LCM type, with its jsonschema, generated from
/// lcmtypes/*.lcm at build time (procs/foxglove/gen_lcm_json.py): field names as in the .lcm
/// files, `byte` arrays as base64 strings, non-finite numbers as null, each field's .lcm
/// comment (unit, value meaning "invalid") as its schema description.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ucon/foxglove/lcm_json_gen.hpp"

namespace ucon {
namespace foxglove {

class JsonWriter;

/// One ucon LCM type.
struct LcmTypeInfo {
  const char* name;         ///< "ucon.point_cloud_t"
  int64_t fingerprint;      ///< LCM hash: the first 8 bytes of every encoded message
  const char* json_schema;  ///< jsonschema of its JSON encoding (title = name)
  /// Decodes `size` bytes and appends the JSON object to `out`; false (nothing written) when
  /// the bytes do not decode as this type, exactly to their end.
  bool (*to_json)(const void* data, int size, JsonWriter& out);
  /// True when the first field is `int64_t utime` in message (sensor or simulation) time;
  /// false for types without one and for those whose utime is the wall clock
  /// (log_metadata_t, supervisor_status_t), as their .lcm comments say.
  bool has_message_time;
};

/// The utime of an encoded message whose type has_message_time (the 8 bytes after the
/// fingerprint, big-endian) [us]; 0 when `size` is too short.
int64_t encodedUtime(const void* data, std::size_t size);

/// Every ucon type, sorted by name.
const std::vector<LcmTypeInfo>& lcmTypes();

/// The type whose fingerprint starts `data`; nullptr when it is shorter than 8 bytes or no
/// ucon type has that fingerprint.
const LcmTypeInfo* findLcmType(const void* data, std::size_t size);

/// The type named `name` ("ucon.robot_pose_t"); nullptr if there is none.
const LcmTypeInfo* findLcmTypeByName(const char* name);

}  // namespace foxglove
}  // namespace ucon
