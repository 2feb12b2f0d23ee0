#pragma once
/// @file foxglove_schemas.hpp
/// jsonschema texts of the Foxglove well-known message types that the exporters write:
/// foxglove.PointCloud, foxglove.FrameTransform, foxglove.PoseInFrame, foxglove.SceneUpdate
/// and foxglove.Grid. Foxglove recognises these by their schema name; the texts describe the
/// fields these tools fill, with Foxglove's field names and JSON conventions (times as
/// {sec, nsec}, bytes as base64 strings, enumerations as integers). Also ucon.StatusView, the
/// view of a process's status message that plots can pick values from by name.

#include <string>

namespace ucon {
namespace foxglove {

/// Foxglove's NumericType values for packed fields (PointCloud, Grid).
enum class NumericType : int { kUint8 = 1, kInt8 = 2, kUint16 = 3, kInt16 = 4, kUint32 = 5,
                               kInt32 = 6, kFloat32 = 7, kFloat64 = 8 };

/// LinePrimitive types.
enum class LineType : int { kLineStrip = 0, kLineLoop = 1, kLineList = 2 };

/// SceneEntityDeletion types.
enum class DeletionType : int { kMatchingId = 0, kAll = 1 };

/// The jsonschema of `schema_name` ("foxglove.PointCloud", ..., "ucon.StatusView"); empty for
/// a name that is not one of the six above.
const std::string& foxgloveSchema(const std::string& schema_name);

}  // namespace foxglove
}  // namespace ucon
